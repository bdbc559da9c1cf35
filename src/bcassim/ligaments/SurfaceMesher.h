// Tetrahedral meshing of a closed triangle surface (a CT liver segmentation) with CGAL Mesh_3,
// after repairing the surface (duplicates, degeneracies, orientation, holes). Output in metres.
#pragma once
#include <string>
#include <vector>

#include "bcassim/mesh/TetMesh.h"
#include "bcassim/mesh/TriMesh.h"

namespace bcassim {

struct SurfaceMeshingOptions {
  double scale = 1e-3;          // multiplies input coordinates: 1e-3 turns millimetres into metres
  int targetNodes = 2150;       // wanted node count (thesis §5.1: 2,150 estimation, ~14,300 truth)
  double nodeTolerance = 0.15;  // accept a mesh within +-15 % of targetNodes
  int maxAttempts = 3;          // meshing runs to land within the tolerance; the closest is kept
  int maxHoleEdges = 200;  // border loops up to this many edges are filled; a larger one sends the
                           // surface to the ray-vote route (SurfaceMeshingReport)
  double facetAngleDeg = 25;   // lower bound of surface triangle angles
  double radiusEdgeRatio = 3;  // upper bound of tet circumradius / shortest edge
  // Sliver exudation raises the minimum dihedral angle but its results vary from run to run
  // (observed: +-2 nodes on a 200-node sphere), so it is off for reproducible meshes.
  // Perturbation (time-bounded) is never used.
  bool exude = false;
};

// What the repair and meshing did, for logs and the batch report. Lengths in metres.
struct SurfaceMeshingReport {
  int inputVertices = 0, inputFaces = 0;
  int mergedVertices = 0;     // duplicate points merged into one
  int removedFaces = 0;       // degenerate or duplicate faces dropped
  int flippedFaces = 0;       // faces reversed for a consistent outward orientation
  int holesFilled = 0;        // border loops closed by triangulate_hole
  int components = 0;         // connected components after repair (only the largest is kept)
  int genus = 0;              // handles of the kept component (0 for a sphere-like liver)
  int selfIntersections = 0;  // pairs of intersecting faces in the repaired surface
  double surfaceVolume = 0;   // enclosed by the repaired surface, m^3
  double cellSize = 0;        // Mesh_3 size criterion of the kept run, m
  int attempts = 0;           // meshing runs made
  int outputNodes = 0, outputTets = 0;
  double meshVolume = 0;  // sum of tet volumes, m^3
  double minDihedralDeg = 0;
  double seconds = 0;  // wall time of repair and meshing
  // When the repaired surface was not usable (a border loop too large to fill, a hole that
  // cannot be filled, no enclosed volume, or a mesh volume more than 5 % off the surface's, as
  // when hole fills along an orientation seam fold it onto itself), the input soup is meshed from
  // a ray-vote inside test instead (odd crossings along most of 7 rays: no orientation needed,
  // small holes outvoted). Then surfaceVolume is the volume that test encloses (sampled on a
  // grid), `repaired` the mesh's boundary, and components counts the tet pieces before the
  // largest was kept.
  bool insideTestDomain = false;
  std::string repairProblem;     // why the repaired surface was not meshed; empty otherwise
  double closeVotes = 0;         // samples won by one ray (4 to 3) per sample called inside
  double boundaryDeviation = 0;  // largest distance of the mesh's boundary nodes and face
                                 // centroids to the input surface, m
};

struct SurfaceMeshingResult {
  TetMesh mesh;      // positively oriented tets, validated, region all 0
  TriMesh repaired;  // the repaired, scaled surface that was meshed (outward, metres)
  SurfaceMeshingReport report;
};

// Repairs `surface` (coordinates multiplied by options.scale) and tetrahedralises it; a surface
// the repair cannot close is meshed from its ray-vote inside test (see SurfaceMeshingReport).
// `source` names the input in error messages. Deterministic (unless options.exude): the same input
// gives the same mesh. Throws InputError, e.g. "half.obj: a border loop of 412 edges is too large
// to fill (limit 200); nor does it enclose a clear inside (votes 4 to 3 at 31 % of the inside,
// limit 5 %)", when neither route gives a volume, or meshing yields no tets.
SurfaceMeshingResult meshSurface(const TriMesh& surface, const SurfaceMeshingOptions& options,
                                 const std::string& source = "surface");

// What the repair and meshing did, in words ("meshed from the ray-vote inside test (...); 3
// holes filled; ..."); empty for an input that needed nothing.
std::string describeMeshing(const SurfaceMeshingReport& report);

// One line of the batch report: the file, its outcome, and the report or the reason it failed.
struct LiverMeshingOutcome {
  std::string file;     // path relative to the data directory
  bool ok = false;      // meshed, validated, node count in tolerance, tet volume within 5 % of
                        // the repaired surface's
  std::string problem;  // why not, or the repairs made (empty for an input that needed none)
  SurfaceMeshingReport report;
};

// Meshes every livers/*.obj (millimetres, sorted by name) and sofa-liver/liver-smooth.obj
// (scaled so its largest bounding-box side is 0.20 m) under `dataDir`. Failures are recorded,
// not thrown; throws InputError only when `dataDir`/livers does not exist.
std::vector<LiverMeshingOutcome> meshAllLivers(const std::string& dataDir,
                                               const SurfaceMeshingOptions& options = {});

}  // namespace bcassim
