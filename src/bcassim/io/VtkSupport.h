// Internal helpers of the io module around VTK: silencing VTK's own error printing while turning
// its errors into one-line InputErrors, and conversions between Eigen and VTK arrays.
#pragma once
#include <vtkSmartPointer.h>

#include <Eigen/Core>
#include <memory>
#include <mutex>
#include <string>

#include "bcassim/io/FieldSet.h"

class vtkDataSet;
class vtkOutputWindow;
class vtkPoints;

namespace bcassim::io {

// While alive, VTK errors and warnings go to this object instead of stderr (the library never
// prints): both VTK's output window and its logger, which prints on its own, are redirected.
// They are process-wide, so captures are serialised by a mutex.
class VtkErrorCapture {
 public:
  VtkErrorCapture();
  ~VtkErrorCapture();
  VtkErrorCapture(const VtkErrorCapture&) = delete;
  VtkErrorCapture& operator=(const VtkErrorCapture&) = delete;

  bool hasError() const;
  // The first error's message without VTK's source location, on one line.
  std::string firstError() const;
  bool hasWarning() const;
  std::string firstWarning() const;

 private:
  std::unique_lock<std::recursive_mutex> lock_;
  vtkSmartPointer<vtkOutputWindow> previous_;
  vtkSmartPointer<vtkOutputWindow> capture_;
  int loggerVerbosity_;
};

Eigen::MatrixX3d pointsOf(vtkDataSet* data);
vtkSmartPointer<vtkPoints> toVtkPoints(const Eigen::MatrixX3d& V);

// Adds `fields` to `data`, checking their sizes against its points and cells; throws
// std::invalid_argument naming the field on a size mismatch (a caller bug, not bad input).
void attachFields(vtkDataSet* data, const FieldSet& fields);

// Throws InputError "<path>: <what>: <VTK's message>" when `capture` saw an error.
void throwIfVtkError(const VtkErrorCapture& capture, const std::string& path,
                     const std::string& what);

// Throws OutputError "<path>: cannot write file: <VTK's message>" when a writer's `capture` saw an
// error (a full disk, a folder that cannot be written).
void throwIfVtkWriteError(const VtkErrorCapture& capture, const std::string& path);

// As throwIfVtkError for the legacy readers, which report an unparsable ASCII value only as
// "Unrecognized keyword: <value>" once they have lost their place: the value is looked up in the
// file so the message names its line, e.g. "cube.vtk:7: value 'nan' is not a finite number".
void throwIfLegacyVtkError(const VtkErrorCapture& capture, const std::string& path,
                           const std::string& what);

// Throws InputError when a coordinate is NaN or infinite, naming the point.
void requireFinitePoints(const Eigen::MatrixX3d& V, const std::string& path);

}  // namespace bcassim::io
