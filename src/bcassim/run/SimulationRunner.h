// Runs a Scene forward in time and writes its results: a ParaView series, marker tracks and
// per-step timings; with variants, runs each and compares their marker displacements.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "bcassim/scene/Scene.h"

namespace bcassim {

// Where a run stands, reported after every step.
struct RunProgress {
  std::string variant;                // name of the scene being run ("base" or a variant's)
  int variantIndex = 0;               // 0 for the base
  int numVariants = 1;                // base included
  int step = 0, steps = 0;            // steps done / to do in this variant
  int stepsDone = 0, stepsTotal = 0;  // over all variants
  double elapsedSeconds = 0;          // since runSimulation started
  double meanStepMs = 0;              // mean wall time of this variant's steps so far
};
using ProgressCallback = std::function<void(const RunProgress&)>;

struct RunResult {
  std::string name;
  std::string outDir;                // where its files went
  int steps = 0, frames = 0;         // frames written to the .pvd (0 without pvd)
  double meanStepMs = 0;             // mean wall time of one step (integration only)
  double wallSeconds = 0;            // the whole run, output included
  double maxMarkerDisplacement = 0;  // m, over markers and steps
  double maxNodeDisplacement = 0;    // m, over nodes and steps
  // Marker displacements against the base run, relative to the base's largest marker
  // displacement: at the final time (max_i |u_i - u_ref,i| / max_i |u_ref,i|), and over the
  // output times t, every output.every steps and the last (max over t, i of |u_i - u_ref,i| /
  // max over t, i of |u_ref,i|). 0 for the base.
  double relativeDifferenceFinal = 0;
  double relativeDifferenceAll = 0;
};

struct SimulationResult {
  std::vector<RunResult> runs;  // base first, then the variants in scene order
  double wallSeconds = 0;
};

// Runs the base scene into outDir and each variant into outDir/<variant name>, writing in each:
//   simulation.pvd + simulation_NNNNNN.vtu (every output.every steps, the first and last step;
//     point fields displacement_m, displacement_magnitude_m, cell field von_mises_Pa) and
//     simulation_markers_*.vtp / simulation_springs_*.vtp parts when there are markers / springs
//   markers.csv  time,marker,x,y,z after every step (s, index, m), flushed as it goes
//   validation.csv  the same for the validation points, with a first frame at t = 0 (rest)
//   timing.csv   per-step wall times in ms, iterations and retries (halved steps or increments)
// and with variants, outDir/variants.csv (name, relative differences, mean step time).
// progress (may be empty) is called after every step. Throws NumericalError when a step fails even
// when cut down to time.min_dt, "<scene>: step N (t = T s): <what failed>" (an inverted element,
// a linear or Newton solve that did not converge), and InputError when a file cannot be written.
//
// A checkpoint (outDir/checkpoint.bin, SimulationCheckpoint.h) is written at every output step;
// with `resume`, the run continues from it: the CSV files are cut back to its step and appended
// to, the .pvd keeps its frames. Resuming is for scenes without variants (InputError otherwise).
SimulationResult runSimulation(const Scene& scene, const std::string& outDir,
                               const ProgressCallback& progress = {}, bool resume = false);

}  // namespace bcassim
