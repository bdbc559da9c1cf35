// Reading the `assimilation:` section of a scene (docs/assimilation-format.md) with located
// one-line errors, and putting marker tracks on the scene's time grid.
#pragma once
#include <yaml-cpp/yaml.h>

#include "bcassim/mechanics/MechanicalModel.h"
#include "bcassim/scene/AssimilationSettings.h"
#include "bcassim/scene/YamlReader.h"

namespace bcassim {

// What the section is checked against: the scene read so far.
struct AssimilationContext {
  const MechanicalModel& model;
  int markers = 0;           // observed points (markers:)
  int validationPoints = 0;  // validation_points:
  double dt = 0.01;          // s
  int steps = 0;
  std::string solverType = "cholmod";  // solver.type
  bool statics = false;                // integrator.type static: every frame an equilibrium
};

// Tracks of `numPoints` points (`pointsName` in messages: "markers") at times timeOffset + k dt,
// k = 0 .. steps; frames past the last step are dropped. Throws InputError naming `file` when it
// holds another number of points or a frame off the grid.
TrackFrames toStepFrames(const MarkerTracks& tracks, const std::string& file, int numPoints,
                         const std::string& pointsName, double dt, int steps, double timeOffset);

namespace yamlio {

// Whether the sigma points of `node` (the scene's `assimilation` section) solve with
// factorized-pcg sharing worker 0's factorisation: reuse_factorization (true by default) with
// tangent: own. The scene's solver.type defaults to factorized-pcg then.
bool sharesSolverFactorization(const YamlSource& source, const YAML::Node& node);

// Reads `node` (the value of the scene's `assimilation` key) and the track files it names.
// Refuses reuse_factorization with a solver.type other than factorized-pcg, and
// reuse_factorization: false with tangent: mean (whose sigma points always share one factor).
AssimilationSettings readAssimilationSettings(const YamlSource& source, const YAML::Node& node,
                                              const AssimilationContext& context);

}  // namespace yamlio
}  // namespace bcassim
