// The binding functions of the Python module, one per room of the C++ tree (python/src/Bind*.cpp),
// called by Module.cpp on the submodules that mirror the rooms.
#pragma once
#include <pybind11/pybind11.h>

namespace bcassim::python {

void bindErrors(pybind11::module_& m);
void bindMesh(pybind11::module_& m);
void bindIo(pybind11::module_& m);
void bindMechanics(pybind11::module_& m);
void bindAssimilation(pybind11::module_& m);
void bindScene(pybind11::module_& m);
void bindAtlas(pybind11::module_& m);
void bindTracking(pybind11::module_& m);
void bindLiver(pybind11::module_& m);
void bindCalibration(pybind11::module_& m);

}  // namespace bcassim::python
