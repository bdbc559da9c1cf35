// The state of a forward run at one step, kept beside its outputs so that `simulate --resume`
// continues a run that was stopped (killed, crashed, out of time) instead of starting over.
#pragma once
#include <Eigen/Core>
#include <string>

namespace bcassim {

struct SimulationCheckpoint {
  int step = 0;          // steps done
  double t = 0;          // s
  Eigen::VectorXd x, v;  // positions (m) and velocities (m/s), 3N node-major
  int frames = 0;        // .pvd frames written so far
  double maxNodeDisplacement = 0, maxMarkerDisplacement = 0;  // m, over the steps so far
  double stepSeconds = 0;                                     // integration wall time so far, s
};

// `key` says which scene a checkpoint belongs to (sizes, dt, integrator): a checkpoint read with
// another key is refused.
// Writes dir/checkpoint.bin through a temporary file and a rename, so that a crash leaves the
// previous checkpoint whole. Throws InputError if it cannot be written.
void writeSimulationCheckpoint(const std::string& dir, const std::string& key,
                               const SimulationCheckpoint& checkpoint);
// Reads dir/checkpoint.bin; throws InputError naming the file when it is missing, damaged or was
// written for another scene (key).
SimulationCheckpoint readSimulationCheckpoint(const std::string& dir, const std::string& key);

}  // namespace bcassim
