#include "bcassim/experiments/liver/AtlasCurve.h"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "bcassim/Error.h"
#include "bcassim/Stopwatch.h"
#include "bcassim/Types.h"
#include "bcassim/atlas/AnnotatedLivers.h"
#include "bcassim/atlas/AtlasTransfer.h"
#include "bcassim/atlas/CurveComparison.h"
#include "bcassim/atlas/LigamentAtlasFile.h"

namespace bcassim {
namespace {

namespace fs = std::filesystem;

// Beside the atlas' own files: which liver it was built without, so that a cache of another
// patient's fold is never taken for this one.
constexpr const char* kExcludedFile = "excluded.txt";

RegistrationOptions registrationOptions(int iterations) {
  RegistrationOptions o;
  o.sigmaV = 0.03;
  o.sigmaW = 0.02;
  o.dataTerm = FaceKernelKind::Varifold;
  o.lbfgs.maxIterations = iterations;
  return o;
}

// The atlas' mean curve and sigma carried and projected onto the patient, into `result`.
void transferOnto(const LigamentAtlas& atlas, const TriMesh& patient, int iterations,
                  double maxRotationDegrees, AtlasCurve& result) {
  const auto t0 = Clock::now();
  const AtlasTransfer transfer = transferAtlas(atlas, patient, registrationOptions(iterations),
                                               true, true, maxRotationDegrees);
  result.transferSeconds = secondsSince(t0);
  result.curve = transfer.curve.mean;
  result.sigma = transfer.curve.sigma;
  result.lower = transfer.curve.lower;
  result.upper = transfer.curve.upper;
  result.rotationDegrees = transfer.rigidReport.rotationDegrees;
  result.poseDoubts = poseDoubts(transfer.rigidReport, maxRotationDegrees);
}

bool cachedFor(const fs::path& dir, const std::string& excluded) {
  std::ifstream in(dir / kExcludedFile);
  std::string name;
  return in && std::getline(in, name) && name == excluded;
}

}  // namespace

AtlasCurve leftOutAtlasCurve(const TriMesh& patient, const LeftOutAtlasOptions& o,
                             const AtlasLog& log) {
  auto say = [&](const std::string& s) {
    if (log) log(s);
  };
  AtlasCurve result;
  const fs::path dir(o.cacheDir);
  LigamentAtlas atlas;
  if (cachedFor(dir, o.exclude)) {
    atlas = readLigamentAtlas(dir.string());
    result.fromCache = true;
    say(fmt::format("atlas without {}: read from {}", o.exclude, dir.string()));
  } else {
    const auto t0 = Clock::now();
    LiverFolder livers = readAnnotatedLivers(o.liverDir, 2, o.scale);
    std::erase_if(livers.subjects, [&](const AtlasSubject& s) { return s.name == o.exclude; });
    if (livers.subjects.size() < 2)
      throw InputError(fmt::format(
          "{}: {} usable livers besides {}; expected at least 2 to build an atlas without it",
          o.liverDir, livers.subjects.size(), o.exclude));
    result.atlasLivers = static_cast<int>(livers.subjects.size());
    say(fmt::format("atlas of {} livers without {} (minutes)", livers.subjects.size(), o.exclude));
    LigamentAtlasOptions ao;
    ao.registration = registrationOptions(60);
    ao.centre = CurveCentre::Trimmed;
    atlas = buildLigamentAtlas(livers.subjects, ao, log);
    const fs::path partial = dir.string() + ".partial";
    fs::remove_all(partial);
    writeLigamentAtlas(partial.string(), atlas);
    std::ofstream(partial / kExcludedFile) << o.exclude << '\n';
    fs::remove_all(dir);
    fs::rename(partial, dir);
    result.buildSeconds = secondsSince(t0);
  }
  transferOnto(atlas, patient, o.transferIterations, 180.0, result);
  return result;
}

AtlasCurve transferredAtlasCurve(const TriMesh& patient, const std::string& atlasDir,
                                 int transferIterations) {
  AtlasCurve result;
  const LigamentAtlas atlas = readLigamentAtlas(atlasDir);
  result.fromCache = true;
  transferOnto(atlas, patient, transferIterations, kScannerFrameMaxRotationDegrees, result);
  return result;
}

std::vector<double> distancesToPolyline(const Eigen::MatrixX3d& curve,
                                        const Eigen::MatrixX3d& reference) {
  std::vector<double> d;
  for (Eigen::Index i = 0; i < curve.rows(); ++i)
    d.push_back(distanceToPolyline(curve.row(i).transpose(), reference));
  return d;
}

}  // namespace bcassim
