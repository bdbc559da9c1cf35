#include "bcassim/experiments/tracked/LeftOutAtlasCurve.h"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "bcassim/Error.h"
#include "bcassim/Stopwatch.h"
#include "bcassim/atlas/AnnotatedLivers.h"
#include "bcassim/atlas/AtlasTransfer.h"
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

bool cachedFor(const fs::path& dir, const std::string& excluded) {
  std::ifstream in(dir / kExcludedFile);
  std::string name;
  return in && std::getline(in, name) && name == excluded;
}

}  // namespace

LeftOutAtlasCurve leftOutAtlasCurve(const TriMesh& patient, const LeftOutAtlasOptions& o,
                                    const AtlasLog& log) {
  auto say = [&](const std::string& s) {
    if (log) log(s);
  };
  LeftOutAtlasCurve result;
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
  const auto t1 = Clock::now();
  const AtlasTransfer transfer =
      transferAtlas(atlas, patient, registrationOptions(100), true, true);
  result.transferSeconds = secondsSince(t1);
  result.curve = transfer.curve.mean;
  result.sigma = transfer.curve.sigma;
  return result;
}

}  // namespace bcassim
