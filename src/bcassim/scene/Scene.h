// A simulation scene ready to run: the mechanical model built from a YAML scene file, how to
// integrate it, what to observe (markers) and what to write. Built by loadScene (SceneLoader.h).
#pragma once
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bcassim/mechanics/ImplicitEuler.h"
#include "bcassim/mechanics/MechanicalModel.h"
#include "bcassim/mechanics/StaticSolver.h"
#include "bcassim/mechanics/solvers/FactorizedPcgSolver.h"
#include "bcassim/mesh/BarycentricMap.h"
#include "bcassim/scene/AssimilationSettings.h"

namespace bcassim {

enum class IntegratorKind { ImplicitEuler, Static };

struct LinearSolverChoice {
  std::string type = "cholmod";  // a name makeLinearSolver accepts
  RefreshPolicy policy;          // factorized-pcg refresh; relTol also for cg and jacobi-pcg
};

// Points followed through the simulation and written as tracks, mapped into the rest mesh.
struct MarkerSet {
  std::vector<MappedPoint> points;
  Eigen::MatrixX3d rest;  // #markers by 3 rest positions, m
};

struct OutputSettings {
  int every = 10;   // steps between ParaView frames (the first and last step are always written)
  bool pvd = true;  // write the .pvd series (mesh, markers, springs)
};

struct Scene {
  // The model has no empty state, so a scene starts from one.
  explicit Scene(MechanicalModel m) : model(std::move(m)) {}

  std::string name = "base";  // "base", or the variant's name
  std::string sourceFile;     // scene file, as given

  MechanicalModel model;
  IntegratorKind integrator = IntegratorKind::ImplicitEuler;
  ImplicitEulerOptions implicitEuler;  // dt also gives the time step of static runs
  StaticOptions statics;
  LinearSolverChoice solver;
  int steps = 100;

  MarkerSet markers;
  // Points whose error against the truth validates an estimate (validation_points:); written as
  // validation.csv by simulate runs.
  MarkerSet validation;
  // Hidden structures (tumours, vessels) never observed: simulate writes their tracks as
  // hidden.csv; assimilate predicts them with their uncertainty every step (hidden_points.csv).
  MarkerSet hidden;
  OutputSettings output;
  // The scene's assimilation: section, read by every command; only assimilate and validate use it.
  std::optional<AssimilationSettings> assimilation;

  // Other versions of this scene (the base's YAML with the variant's keys merged in), run after
  // it and compared with it. Variants have no variants of their own.
  std::vector<Scene> variants;

  double dt() const { return implicitEuler.dt; }
};

}  // namespace bcassim
