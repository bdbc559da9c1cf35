// estimates.csv of an assimilation run: one row per step and parameter, step,time_s,parameter,
// mean,stddev (physical units), step 0 holding the prior. Written flushed per step; `validate`
// reads the last step's values back.
#pragma once
#include <Eigen/Core>
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace bcassim {

class EstimatesWriter {
 public:
  // Truncates `path`, writes the header. Throws InputError if it cannot be written.
  EstimatesWriter(const std::string& path, std::vector<std::string> names);
  // Resumed runs: keeps the rows of steps up to `resumeStep` and appends.
  EstimatesWriter(const std::string& path, std::vector<std::string> names, int resumeStep);
  // One row per parameter, then a flush, so a killed run leaves every finished step.
  void write(int step, double time, const Eigen::VectorXd& mean, const Eigen::VectorXd& stddev);

 private:
  std::string path_;
  std::vector<std::string> names_;
  std::ofstream out_;
};

struct FinalEstimate {
  int step = 0;
  double mean = 0.0, stddev = 0.0;
};

// The last row of each parameter in an estimates.csv. Throws InputError naming the line for a
// malformed file, e.g. "estimates.csv:7: expected 5 fields (step,time_s,parameter,mean,stddev),
// got 3".
std::map<std::string, FinalEstimate> readFinalEstimates(const std::string& path);

}  // namespace bcassim
