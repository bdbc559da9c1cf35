#include "bcassim/io/VtkSupport.h"

#include <fmt/format.h>
#include <vtkCellData.h>
#include <vtkDataSet.h>
#include <vtkDoubleArray.h>
#include <vtkLogger.h>
#include <vtkObjectFactory.h>
#include <vtkOutputWindow.h>
#include <vtkPointData.h>
#include <vtkPoints.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "bcassim/Error.h"
#include "bcassim/io/TextLines.h"

namespace bcassim::io {
namespace {

class CapturingOutputWindow : public vtkOutputWindow {
 public:
  static CapturingOutputWindow* New();
  vtkTypeMacro(CapturingOutputWindow, vtkOutputWindow);

  void DisplayText(const char*) override {}
  void DisplayErrorText(const char* text) override {
    if (text) errors.emplace_back(text);
  }
  void DisplayWarningText(const char* text) override {
    if (text) warnings.emplace_back(text);
  }
  void DisplayGenericWarningText(const char* text) override { DisplayWarningText(text); }
  void DisplayDebugText(const char*) override {}

  std::vector<std::string> errors;
  std::vector<std::string> warnings;
};
vtkStandardNewMacro(CapturingOutputWindow);

std::recursive_mutex& vtkOutputMutex() {
  static std::recursive_mutex mutex;
  return mutex;
}

// VTK messages read "ERROR: In <file>, line <n>\n<Class> (<address>): <message>\n\n", or
// "Generic Warning: In <file>, line <n>\n<message>" from code outside an object.
std::string messageOf(const std::string& text) {
  std::string body = text;
  const size_t eol = body.find('\n');
  if (eol != std::string::npos && body.find(": In ") < eol && body.find(", line ") < eol)
    body = body.substr(eol + 1);
  const size_t colon = body.find("): ");
  if (colon != std::string::npos && colon < body.find('\n')) body = body.substr(colon + 3);
  std::string out;
  for (char c : body) {
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
    if (c == ' ' && (out.empty() || out.back() == ' ')) continue;
    out += c;
  }
  while (!out.empty() && out.back() == ' ') out.pop_back();
  // The caller's message names the file already.
  const size_t forFile = out.find(" for file: ");
  if (forFile != std::string::npos) out.erase(forFile);
  return out;
}

void checkSize(Eigen::Index got, Eigen::Index expected, const std::string& name, const char* kind) {
  if (got != expected)
    throw std::invalid_argument(
        fmt::format("{} field '{}' has {} values; expected {}", kind, name, got, expected));
}

}  // namespace

VtkErrorCapture::VtkErrorCapture() : lock_(vtkOutputMutex()) {
  previous_ = vtkOutputWindow::GetInstance();
  capture_ = vtkSmartPointer<CapturingOutputWindow>::New();
  vtkOutputWindow::SetInstance(capture_);
  // vtkLogger has no getter for the stderr level; the cut-off equals it unless log files or
  // callbacks ask for more, which the library does not set up.
  loggerVerbosity_ = vtkLogger::GetCurrentVerbosityCutoff();
  vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
}

VtkErrorCapture::~VtkErrorCapture() {
  vtkLogger::SetStderrVerbosity(static_cast<vtkLogger::Verbosity>(loggerVerbosity_));
  vtkOutputWindow::SetInstance(previous_);
}

bool VtkErrorCapture::hasError() const {
  return !static_cast<CapturingOutputWindow*>(capture_.Get())->errors.empty();
}

bool VtkErrorCapture::hasWarning() const {
  return !static_cast<CapturingOutputWindow*>(capture_.Get())->warnings.empty();
}

std::string VtkErrorCapture::firstWarning() const {
  const auto& warnings = static_cast<CapturingOutputWindow*>(capture_.Get())->warnings;
  return warnings.empty() ? std::string() : messageOf(warnings.front());
}

std::string VtkErrorCapture::firstError() const {
  const auto& errors = static_cast<CapturingOutputWindow*>(capture_.Get())->errors;
  return errors.empty() ? std::string() : messageOf(errors.front());
}

Eigen::MatrixX3d pointsOf(vtkDataSet* data) {
  const vtkIdType n = data->GetNumberOfPoints();
  Eigen::MatrixX3d V(n, 3);
  double p[3];
  for (vtkIdType i = 0; i < n; ++i) {
    data->GetPoint(i, p);
    V.row(i) << p[0], p[1], p[2];
  }
  return V;
}

vtkSmartPointer<vtkPoints> toVtkPoints(const Eigen::MatrixX3d& V) {
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(V.rows());
  for (Eigen::Index i = 0; i < V.rows(); ++i) points->SetPoint(i, V(i, 0), V(i, 1), V(i, 2));
  return points;
}

void attachFields(vtkDataSet* data, const FieldSet& fields) {
  const vtkIdType np = data->GetNumberOfPoints();
  const vtkIdType nc = data->GetNumberOfCells();
  for (const auto& [name, values] : fields.pointScalars) {
    checkSize(values.size(), np, name, "point");
    auto array = vtkSmartPointer<vtkDoubleArray>::New();
    array->SetName(name.c_str());
    array->SetNumberOfValues(np);
    for (vtkIdType i = 0; i < np; ++i) array->SetValue(i, values(i));
    data->GetPointData()->AddArray(array);
  }
  for (const auto& [name, values] : fields.pointVectors) {
    checkSize(values.rows(), np, name, "point");
    auto array = vtkSmartPointer<vtkDoubleArray>::New();
    array->SetName(name.c_str());
    array->SetNumberOfComponents(3);
    array->SetNumberOfTuples(np);
    for (vtkIdType i = 0; i < np; ++i)
      array->SetTuple3(i, values(i, 0), values(i, 1), values(i, 2));
    data->GetPointData()->AddArray(array);
  }
  for (const auto& [name, values] : fields.cellScalars) {
    checkSize(values.size(), nc, name, "cell");
    auto array = vtkSmartPointer<vtkDoubleArray>::New();
    array->SetName(name.c_str());
    array->SetNumberOfValues(nc);
    for (vtkIdType i = 0; i < nc; ++i) array->SetValue(i, values(i));
    data->GetCellData()->AddArray(array);
  }
}

void throwIfVtkError(const VtkErrorCapture& capture, const std::string& path,
                     const std::string& what) {
  if (!capture.hasError()) return;
  const std::string message = capture.firstError();
  throw InputError(message.empty() ? fmt::format("{}: {}", path, what)
                                   : fmt::format("{}: {}: {}", path, what, message));
}

void throwIfVtkWriteError(const VtkErrorCapture& capture, const std::string& path) {
  if (!capture.hasError()) return;
  const std::string message = capture.firstError();
  throw OutputError(message.empty() ? fmt::format("{}: cannot write file", path)
                                    : fmt::format("{}: cannot write file: {}", path, message));
}

void throwIfLegacyVtkError(const VtkErrorCapture& capture, const std::string& path,
                           const std::string& what) {
  // Short data (a truncated file) is only a warning to the legacy readers.
  if (!capture.hasError()) {
    const std::string warning = capture.firstWarning();
    if (warning.rfind("Error reading", 0) == 0)
      throw InputError(fmt::format("{}: {}: {}", path, what, warning));
    return;
  }
  const std::string message = capture.firstError();
  const std::string prefix = "Unrecognized keyword: ";
  if (capture.hasWarning() && message.rfind(prefix, 0) == 0) {
    const std::string token = message.substr(prefix.size());
    constexpr int kHeaderLines = 4;  // version, title, ASCII|BINARY, DATASET
    TextLines in(path);
    while (in.next()) {
      if (in.lineNumber() <= kHeaderLines) continue;
      const auto fields = splitBlanks(in.line());
      if (std::find(fields.begin(), fields.end(), token) == fields.end()) continue;
      double value = 0;
      if (parseDouble(token, value) && !std::isfinite(value))
        in.fail(fmt::format("value '{}' is not a finite number", excerpt(token)));
      in.fail(
          fmt::format("cannot read legacy VTK data at '{}'; expected a number, or section "
                      "counts that match the data",
                      excerpt(token)));
    }
  }
  throwIfVtkError(capture, path, what);
}

void requireFinitePoints(const Eigen::MatrixX3d& V, const std::string& path) {
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite(V(i, k)))
        throw InputError(
            fmt::format("{}: point {} has a non-finite coordinate ({}); expected a "
                        "finite number",
                        path, i, V(i, k)));
}

}  // namespace bcassim::io
