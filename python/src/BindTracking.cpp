// bcassim.tracking: identities of unlabelled marker detections over frames (optimal gated
// assignment, motion prediction) and rigid registration of a partial point cloud to a surface
// (trimmed point-to-plane ICP from several starts). Metres, seconds.
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "Bindings.h"
#include "bcassim/tracking/MarkerTracker.h"
#include "bcassim/tracking/SurfaceRegistration.h"

namespace py = pybind11;
using namespace pybind11::literals;

namespace bcassim::python {

void bindTracking(py::module_& m) {
  py::class_<DetectionFrame>(m, "DetectionFrame", "One camera frame: time (s), #d x 3 points (m)")
      .def(py::init([](double time, Eigen::MatrixX3d points) {
             return DetectionFrame{time, std::move(points)};
           }),
           "time"_a, "points"_a)
      .def_readwrite("time", &DetectionFrame::time)
      .def_readwrite("points", &DetectionFrame::points);

  py::class_<TrackerOptions>(m, "TrackerOptions")
      .def(py::init([](const std::string& assignment, const std::string& prediction, double gate,
                       int confirmFrames, int maxMissedFrames, double noise, double acceleration) {
             TrackerOptions o;
             if (assignment == "optimal")
               o.assignment = AssignmentMethod::Optimal;
             else if (assignment == "greedy")
               o.assignment = AssignmentMethod::Greedy;
             else
               throw py::value_error("assignment: expected 'optimal' or 'greedy', got '" +
                                     assignment + "'");
             if (prediction == "constant-velocity")
               o.prediction = MotionPrediction::ConstantVelocity;
             else if (prediction == "last-position")
               o.prediction = MotionPrediction::LastPosition;
             else
               throw py::value_error(
                   "prediction: expected 'constant-velocity' or 'last-position', got '" +
                   prediction + "'");
             o.gate = gate;
             o.confirmFrames = confirmFrames;
             o.maxMissedFrames = maxMissedFrames;
             o.measurementNoise = noise;
             o.accelerationNoise = acceleration;
             return o;
           }),
           "assignment"_a = "optimal", "prediction"_a = "constant-velocity", "gate"_a = 0.01,
           "confirm_frames"_a = 3, "max_missed_frames"_a = 10, "measurement_noise"_a = 0.001,
           "acceleration_noise"_a = 0.1,
           "gate and measurement_noise in m, acceleration_noise in m/s^2");

  py::class_<Track>(m, "Track", "A confirmed marker: id, frames it was seen in, its detection row")
      .def_readonly("id", &Track::id)
      .def_readonly("frames", &Track::frames)
      .def_readonly("detections", &Track::detections);

  py::class_<MarkerTracker>(m, "MarkerTracker", "Labels frames of unlabelled detections online")
      .def(py::init<const TrackerOptions&>(), "options"_a = TrackerOptions())
      .def(
          "add_frame",
          [](MarkerTracker& t, const DetectionFrame& frame) {
            std::vector<std::string> report;
            std::vector<int> ids = t.addFrame(frame, report);
            return py::make_tuple(ids, report);
          },
          "frame"_a,
          "(ids, report): the track id of each detection (-1: none yet) and one line per input "
          "problem of this frame")
      .def_property_readonly("tracks", &MarkerTracker::tracks);

  m.def(
      "track_markers",
      [](const std::vector<DetectionFrame>& frames, const TrackerOptions& options) {
        TrackingResult r;
        {
          py::gil_scoped_release release;
          r = trackMarkers(frames, options);
        }
        return py::make_tuple(r.ids, r.tracks, r.report);
      },
      "frames"_a, "options"_a = TrackerOptions(),
      "(ids per frame, tracks, report) for a whole recording");

  py::class_<SurfaceRegistration>(m, "SurfaceRegistration")
      .def_readonly("transform", &SurfaceRegistration::transform, "points' frame -> surface frame")
      .def_readonly("rms", &SurfaceRegistration::rms, "m, of the kept points")
      .def_readonly("overlap", &SurfaceRegistration::overlap, "kept points / all points")
      .def_readonly("iterations", &SurfaceRegistration::iterations)
      .def_readonly("converged", &SurfaceRegistration::converged,
                    "the refinement met the tolerance before max_iterations")
      .def_readonly("last_move", &SurfaceRegistration::lastMove,
                    "m, how far its last iteration moved a point");
  m.def(
      "register_points_to_surface",
      [](const Eigen::MatrixX3d& points, const TriMesh& surface, double keepFraction,
         const std::optional<RigidTransform>& initial, double medianFactor) {
        SurfaceRegistrationOptions o;
        o.keepFraction = keepFraction;
        o.medianFactor = medianFactor;
        if (initial) o.initial = *initial;
        py::gil_scoped_release release;
        return registerPointsToSurface(points, surface, o);
      },
      "points"_a, "surface"_a, "keep_fraction"_a = 1.0, "initial"_a = py::none(),
      "median_factor"_a = SurfaceRegistrationOptions{}.medianFactor,
      "Rigid transform moving a (partial) point cloud onto a surface: trimmed point-to-plane ICP "
      "from several start rotations; keep_fraction: expected inlier fraction; median_factor: "
      "points farther than this times the median distance are left out (0: none; a dozen "
      "markers: 0)");
}

}  // namespace bcassim::python
