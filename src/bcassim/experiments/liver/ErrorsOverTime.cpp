#include "bcassim/experiments/liver/ErrorsOverTime.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "bcassim/Error.h"
#include "bcassim/io/CsvTracks.h"
#include "bcassim/run/ValidationErrors.h"

namespace bcassim {

StepSeries validationErrorSeries(const std::string& modelCsv, const std::string& truthCsv) {
  const MarkerTracks a = readMarkerTracks(modelCsv);
  const MarkerTracks b = readMarkerTracks(truthCsv);
  if (a.frames.size() != b.frames.size() || a.numMarkers != b.numMarkers)
    throw InputError(fmt::format("{}: {} frames of {} points, but the truth {} has {} of {}",
                                 modelCsv, a.frames.size(), a.numMarkers, truthCsv, b.frames.size(),
                                 b.numMarkers));
  StepSeries s;
  for (size_t k = 1; k < a.frames.size(); ++k) {  // frame 0 is the rest state
    const StepError e = stepError(a.frames[k], b.frames[k]);
    s.mean.push_back(1e3 * e.mean);
    s.max.push_back(1e3 * e.max);
  }
  return s;
}

ErrorOverTime summariseErrors(const StepSeries& s) {
  ErrorOverTime e;
  e.steps = static_cast<int>(s.mean.size());
  if (e.steps == 0) return e;
  auto meanStd = [](const std::vector<double>& v, double& m, double& sd) {
    m = 0;
    for (double x : v) m += x / static_cast<double>(v.size());
    double var = 0;
    for (double x : v) var += (x - m) * (x - m) / static_cast<double>(v.size());
    sd = std::sqrt(var);
  };
  meanStd(s.mean, e.meanMm, e.meanStdMm);
  meanStd(s.max, e.maxMm, e.maxStdMm);
  for (double x : s.max) e.peakMm = std::max(e.peakMm, x);
  return e;
}

}  // namespace bcassim
