#include "bcassim/run/AssimilationCheckpoint.h"

#include <fmt/format.h>

#include "bcassim/Error.h"
#include "bcassim/io/BinaryArchive.h"

namespace bcassim {
namespace {

Eigen::MatrixXd column(const Eigen::VectorXd& v) { return v; }

void writeState(ArchiveWriter& out, const MechanicalState& s) {
  out.matrix(column(s.x));
  out.matrix(column(s.v));
  out.number(s.t);
}

MechanicalState readState(ArchiveReader& in) {
  MechanicalState s;
  s.x = in.matrix().reshaped();
  s.v = in.matrix().reshaped();
  s.t = in.number();
  return s;
}

}  // namespace

void writeAssimilationCheckpoint(const std::string& path, const std::string& key,
                                 const AssimilationCheckpoint& c) {
  ArchiveWriter out(path);
  writeCheckpointHeader(out, "assimilation", key);
  out.number(c.step);
  out.number(static_cast<double>(c.filter.matrices.size()));
  for (const Eigen::MatrixXd& m : c.filter.matrices) out.matrix(m);
  out.text(c.filter.text);
  writeState(out, c.reference);
  writeState(out, c.initialRun);
  out.number(c.initialRunSteps);
  out.matrix(c.errorSummaries);
  out.text(c.rng);
  out.number(c.innovationSumSquares);
  out.number(static_cast<double>(c.innovationEntries));
  out.matrix(Eigen::Map<const Eigen::VectorXd>(c.stepMs.data(),
                                               static_cast<Eigen::Index>(c.stepMs.size())));
  out.number(c.observedSteps);
  out.number(c.tangentFailures);
  out.matrix(c.parameters);
  out.number(c.motionSumSquares);
  out.number(static_cast<double>(c.motionEntries));
  out.matrix(c.freeRunPath);
  out.matrix(c.freeRunLast);
  out.matrix(c.noiseWindow);
  out.number(c.noiseVariance);
  out.commit();
}

AssimilationCheckpoint readAssimilationCheckpoint(const std::string& path, const std::string& key) {
  ArchiveReader in = openCheckpoint(path, "assimilation", key);
  AssimilationCheckpoint c;
  c.step = static_cast<int>(in.number());
  const auto matrices = static_cast<size_t>(in.number());
  if (matrices > 16) throw InputError(fmt::format("{}: damaged (filter state)", path));
  for (size_t i = 0; i < matrices; ++i) c.filter.matrices.push_back(in.matrix());
  c.filter.text = in.text();
  c.reference = readState(in);
  c.initialRun = readState(in);
  c.initialRunSteps = static_cast<int>(in.number());
  c.errorSummaries = in.matrix();
  c.rng = in.text();
  c.innovationSumSquares = in.number();
  c.innovationEntries = static_cast<long>(in.number());
  const Eigen::MatrixXd ms = in.matrix();
  c.stepMs.assign(ms.data(), ms.data() + ms.size());
  c.observedSteps = static_cast<int>(in.number());
  c.tangentFailures = static_cast<int>(in.number());
  c.parameters = in.matrix();
  c.motionSumSquares = in.number();
  c.motionEntries = static_cast<long>(in.number());
  c.freeRunPath = in.matrix();
  c.freeRunLast = in.matrix();
  c.noiseWindow = in.matrix();
  c.noiseVariance = in.number();
  return c;
}

}  // namespace bcassim
