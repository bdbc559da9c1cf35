// bcassim's typed errors as Python exceptions carrying the same one-line message:
// InputError (a ValueError), OutputError (an InputError), NumericalError (an ArithmeticError).
#include "Bindings.h"
#include "bcassim/Error.h"

namespace py = pybind11;

namespace bcassim::python {

void bindErrors(py::module_& m) {
  // pybind11 tries the translators last-registered first: the derived OutputError goes after
  // InputError so that it is not reported as its base.
  auto& input = py::register_exception<InputError>(m, "InputError", PyExc_ValueError);
  py::register_exception<OutputError>(m, "OutputError", input.ptr());
  py::register_exception<NumericalError>(m, "NumericalError", PyExc_ArithmeticError);
}

}  // namespace bcassim::python
