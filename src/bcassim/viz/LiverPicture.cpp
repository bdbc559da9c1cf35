#include "bcassim/viz/LiverPicture.h"

#include <fmt/format.h>
#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkDoubleArray.h>
#include <vtkLookupTable.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkScalarBarActor.h>
#include <vtkSphereSource.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkWindowToImageFilter.h>
#include <vtkXMLPolyDataReader.h>

#include <cstdlib>
#include <filesystem>

#include "bcassim/Error.h"
#include "bcassim/io/CsvTable.h"
#include "bcassim/io/CsvTracks.h"
#include "bcassim/io/MeshReader.h"
#include "bcassim/io/PointReader.h"
#include "bcassim/io/PvdSeries.h"
#include "bcassim/mesh/BarycentricMap.h"
#include "bcassim/mesh/BoundarySurface.h"

namespace bcassim {
namespace {

namespace fs = std::filesystem;

vtkSmartPointer<vtkActor> sphereActor(const Vec3& c, double radius, const Vec3& rgb,
                                      double opacity) {
  vtkNew<vtkSphereSource> s;
  s->SetCenter(c(0), c(1), c(2));
  s->SetRadius(radius);
  s->SetThetaResolution(24);
  s->SetPhiResolution(16);
  vtkNew<vtkPolyDataMapper> m;
  m->SetInputConnection(s->GetOutputPort());
  auto a = vtkSmartPointer<vtkActor>::New();
  a->SetMapper(m);
  a->GetProperty()->SetColor(rgb(0), rgb(1), rgb(2));
  a->GetProperty()->SetOpacity(opacity);
  return a;
}

// Times (s) of the volume frames of a run's simulation.pvd (part 0), in file order.
std::vector<double> frameTimes(const fs::path& pvd) {
  std::vector<double> times;
  if (!fs::exists(pvd)) return times;
  for (const PvdEntry& e : readPvdIndex(pvd.string()))
    if (e.part == 0) times.push_back(e.time);
  return times;
}

// Index of the frame (times as written) nearest the truth's largest validation displacement.
int frameOfLargestDeformation(const fs::path& truthTracks, const std::vector<double>& times) {
  const MarkerTracks t = readMarkerTracks(truthTracks.string());
  double bestTime = 0, best = -1;
  for (size_t k = 0; k < t.frames.size(); ++k) {
    const double d = (t.frames[k] - t.frames.front()).rowwise().norm().maxCoeff();
    if (d > best) best = d, bestTime = t.times[k];
  }
  int frame = 0;
  for (size_t k = 1; k < times.size(); ++k)
    if (std::abs(times[k] - bestTime) < std::abs(times[frame] - bestTime))
      frame = static_cast<int>(k);
  return frame;
}

int countFrames(const fs::path& dir) {
  int n = 0;
  while (fs::exists(dir / fmt::format("simulation_{:06d}.vtu", n))) ++n;
  return n;
}

}  // namespace

std::string renderLiverPicture(const std::string& runDir, const std::string& png) {
  const char* display = std::getenv("DISPLAY");
  if (!display || !*display)
    return "no X display (VTK 9.1 renders through X): run under `xvfb-run -a` (apt-get install "
           "xvfb)";
  const fs::path dir(runDir);
  for (const char* f : {"coarse.vtu", "fine.vtu", "anatomy.csv", "truth/validation.csv"})
    if (!fs::exists(dir / f)) return (dir / f).string() + " missing";
  // Both runs write their frames at the same times (the scenes of `liver prepare`).
  std::vector<double> times = frameTimes(dir / "estimated" / "simulation.pvd");
  times.resize(std::min<size_t>(
      times.size(),
      static_cast<size_t>(std::min(countFrames(dir / "truth"), countFrames(dir / "estimated")))));
  if (times.empty()) return "no simulation frames in truth/ and estimated/ (simulation.pvd)";
  const int frame = frameOfLargestDeformation(dir / "truth" / "validation.csv", times);
  const double frameTime = times[static_cast<size_t>(frame)];

  const TetMesh coarse = readTetMesh((dir / "coarse.vtu").string());
  const TetMesh fine = readTetMesh((dir / "fine.vtu").string());
  const TetMesh estimated =
      readTetMesh((dir / "estimated" / fmt::format("simulation_{:06d}.vtu", frame)).string());
  const TetMesh truth =
      readTetMesh((dir / "truth" / fmt::format("simulation_{:06d}.vtu", frame)).string());
  if (estimated.numNodes() != coarse.numNodes() || truth.numNodes() != fine.numNodes())
    return "frames do not match coarse.vtu / fine.vtu";
  const CsvTable anatomy = readCsvTable((dir / "anatomy.csv").string());
  const Vec3 center = anatomy.rows.block<1, 3>(0, 0).transpose();
  const Vec3 anterior = anatomy.rows.block<1, 3>(0, 3).transpose();
  const Vec3 superior = anatomy.rows.block<1, 3>(0, 6).transpose();

  // Error of each estimated surface node against the truth at the same material point.
  const BoundarySurface boundary = extractBoundary(coarse);
  const TetLocator locator(fine);
  Eigen::VectorXd truthX(3 * fine.numNodes());
  for (Eigen::Index i = 0; i < fine.numNodes(); ++i) truthX.segment<3>(3 * i) = truth.V.row(i);
  vtkNew<vtkPoints> points;
  vtkNew<vtkDoubleArray> error;
  error->SetName("error_mm");
  for (Eigen::Index i = 0; i < coarse.numNodes(); ++i) {
    const Vec3 p = estimated.V.row(i).transpose();
    points->InsertNextPoint(p(0), p(1), p(2));
    double e = 0;
    if (boundary.vertexNormals.row(i).squaredNorm() > 0) {
      const MappedPoint mp = locator.locate(coarse.V.row(i).transpose());
      e = 1e3 * (interpolate(mp, fine, truthX) - p).norm();
    }
    error->InsertNextValue(e);
  }
  double maxError = 1e-3;
  for (vtkIdType i = 0; i < error->GetNumberOfTuples(); ++i)
    maxError = std::max(maxError, error->GetValue(i));
  vtkNew<vtkCellArray> tris;
  for (Eigen::Index f = 0; f < boundary.F.rows(); ++f) {
    const vtkIdType ids[3] = {boundary.F(f, 0), boundary.F(f, 1), boundary.F(f, 2)};
    tris->InsertNextCell(3, ids);
  }
  vtkNew<vtkPolyData> surface;
  surface->SetPoints(points);
  surface->SetPolys(tris);
  surface->GetPointData()->SetScalars(error);

  vtkNew<vtkLookupTable> lut;
  lut->SetHueRange(0.66, 0.0);  // blue (small) to red (large)
  lut->SetTableRange(0, maxError);
  lut->Build();
  vtkNew<vtkPolyDataMapper> surfaceMapper;
  surfaceMapper->SetInputData(surface);
  surfaceMapper->SetLookupTable(lut);
  surfaceMapper->SetScalarRange(0, maxError);
  vtkNew<vtkActor> liver;
  liver->SetMapper(surfaceMapper);
  liver->GetProperty()->SetOpacity(0.55);

  vtkNew<vtkRenderer> renderer;
  renderer->SetBackground(1, 1, 1);
  renderer->AddActor(liver);

  const fs::path springs = dir / "estimated" / fmt::format("simulation_springs_{:06d}.vtp", frame);
  if (fs::exists(springs)) {
    vtkNew<vtkXMLPolyDataReader> reader;
    reader->SetFileName(springs.c_str());
    vtkNew<vtkPolyDataMapper> m;
    m->SetInputConnection(reader->GetOutputPort());
    m->ScalarVisibilityOff();
    vtkNew<vtkActor> a;
    a->SetMapper(m);
    a->GetProperty()->SetColor(0.35, 0.2, 0.05);
    a->GetProperty()->SetLineWidth(2.5);
    renderer->AddActor(a);
  }
  const fs::path markers = dir / "estimated" / fmt::format("simulation_markers_{:06d}.vtp", frame);
  if (fs::exists(markers)) {
    const Eigen::MatrixX3d m = readPoints(markers.string());
    for (Eigen::Index i = 0; i < m.rows(); ++i)
      renderer->AddActor(sphereActor(m.row(i).transpose(), 0.0025, Vec3(0.1, 0.6, 0.1), 1.0));
  }
  // Tumours: the filter's prediction at this frame's time with its 95 % sphere, and the truth.
  const auto atFrameTime = [&](double t) { return std::abs(t - frameTime) < 1e-6; };
  const fs::path hidden = dir / "estimate" / "hidden_points.csv";
  if (fs::exists(hidden)) {
    const CsvTable t = readCsvTable(hidden.string());
    // The radius with the model error from the innovations where the file has it.
    const int total = t.column("radius95_total_m");
    const int ct = t.column("time_s"), cx = t.column("x_m"),
              cr = total >= 0 ? total : t.column("radius95_m");
    for (Eigen::Index r = 0; r < t.rows.rows(); ++r)
      if (atFrameTime(t.rows(r, ct))) {
        const Vec3 c = t.rows.block<1, 3>(r, cx).transpose();
        renderer->AddActor(
            sphereActor(c, std::max(t.rows(r, cr), 5e-4), Vec3(1.0, 0.8, 0.0), 0.45));
        renderer->AddActor(sphereActor(c, 0.0015, Vec3(0.8, 0.5, 0.0), 1.0));
      }
  }
  const fs::path hiddenTruth = dir / "truth" / "hidden.csv";
  if (fs::exists(hiddenTruth)) {
    const MarkerTracks t = readMarkerTracks(hiddenTruth.string());
    for (size_t k = 0; k < t.frames.size(); ++k)
      if (atFrameTime(t.times[k]))
        for (Eigen::Index i = 0; i < t.frames[k].rows(); ++i)
          renderer->AddActor(
              sphereActor(t.frames[k].row(i).transpose(), 0.0015, Vec3(0.1, 0.1, 0.1), 1.0));
  }

  vtkNew<vtkScalarBarActor> bar;
  bar->SetLookupTable(lut);
  bar->SetTitle("error vs truth (mm)");
  bar->SetNumberOfLabels(5);
  bar->SetMaximumWidthInPixels(90);
  bar->GetTitleTextProperty()->SetColor(0, 0, 0);
  bar->GetLabelTextProperty()->SetColor(0, 0, 0);
  renderer->AddActor2D(bar);
  vtkNew<vtkTextActor> caption;
  caption->SetInput(fmt::format("estimated liver at t = {:.2f} s (largest deformation); brown: "
                                "ligament springs; green: observed markers;\nyellow: tumour 95 % "
                                "spheres (filter), black: true tumours",
                                frameTime)
                        .c_str());
  caption->GetTextProperty()->SetColor(0, 0, 0);
  caption->GetTextProperty()->SetFontSize(14);
  caption->SetDisplayPosition(10, 10);
  renderer->AddActor2D(caption);

  vtkCamera* camera = renderer->GetActiveCamera();
  camera->SetFocalPoint(center(0), center(1), center(2));
  const Vec3 eye = center + 0.45 * anterior;
  camera->SetPosition(eye(0), eye(1), eye(2));
  camera->SetViewUp(superior(0), superior(1), superior(2));
  renderer->ResetCamera();

  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->AddRenderer(renderer);
  window->SetSize(1200, 900);
  window->Render();
  vtkNew<vtkWindowToImageFilter> image;
  image->SetInput(window);
  image->Update();
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(png.c_str());
  writer->SetInputConnection(image->GetOutputPort());
  writer->Write();
  if (!fs::exists(png)) return png + ": not written";
  return {};
}

}  // namespace bcassim
