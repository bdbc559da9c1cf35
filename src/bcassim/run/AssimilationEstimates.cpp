#include "bcassim/run/AssimilationEstimates.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "bcassim/Error.h"
#include "bcassim/io/CsvTruncate.h"
#include "bcassim/io/Files.h"

namespace bcassim {

namespace {
constexpr const char* kHeader = "step,time_s,parameter,mean,stddev";

std::string trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return {};
  return s.substr(a, s.find_last_not_of(" \t\r") - a + 1);
}

double parseField(const std::string& path, int line, const char* name, const std::string& text) {
  double v = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(v))
    throw InputError(
        fmt::format("{}:{}: field {} is not a finite number ('{}')", path, line, name, text));
  return v;
}
}  // namespace

EstimatesWriter::EstimatesWriter(const std::string& path, std::vector<std::string> names)
    : path_(path), names_(std::move(names)), out_(openStepCsv(path, kHeader, std::nullopt)) {}

EstimatesWriter::EstimatesWriter(const std::string& path, std::vector<std::string> names,
                                 int resumeStep)
    : path_(path), names_(std::move(names)), out_(openStepCsv(path, kHeader, resumeStep)) {}

void EstimatesWriter::write(int step, double time, const Eigen::VectorXd& mean,
                            const Eigen::VectorXd& stddev) {
  std::string rows;
  for (size_t i = 0; i < names_.size(); ++i) {
    const auto j = static_cast<Eigen::Index>(i);
    rows += fmt::format("{},{:.9g},{},{:.10g},{:.6g}\n", step, time, names_[i], mean(j), stddev(j));
  }
  out_ << rows;
  out_.flush();
  if (!out_) io::throwWriteError(path_);
}

std::map<std::string, FinalEstimate> readFinalEstimates(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open file");
  std::map<std::string, FinalEstimate> out;
  std::string text;
  int line = 0;
  bool header = false;
  while (std::getline(in, text)) {
    ++line;
    text = trim(text);
    if (text.empty() || text[0] == '#') continue;
    if (!header) {
      if (text != kHeader)
        throw InputError(
            fmt::format("{}:{}: header is '{}'; expected {}", path, line, text, kHeader));
      header = true;
      continue;
    }
    std::vector<std::string> fields;
    std::stringstream s(text);
    for (std::string f; std::getline(s, f, ',');) fields.push_back(trim(f));
    if (fields.size() != 5)
      throw InputError(
          fmt::format("{}:{}: expected 5 fields ({}), got {}", path, line, kHeader, fields.size()));
    FinalEstimate e;
    e.step = static_cast<int>(parseField(path, line, "step", fields[0]));
    e.mean = parseField(path, line, "mean", fields[3]);
    e.stddev = parseField(path, line, "stddev", fields[4]);
    FinalEstimate& slot = out[fields[2]];
    if (e.step >= slot.step) slot = e;
  }
  if (out.empty()) throw InputError(path + ": no estimate (expected rows " + kHeader + ")");
  return out;
}

}  // namespace bcassim
