// `bcassim liver prepare|run`: the liver experiment from one annotated CT surface (thesis §5.1)
// as a command: scenario files only, or the whole run with a summary table, plots and a picture.
#pragma once
#include <CLI/CLI.hpp>
#include <string>

#include "bcassim/experiments/liver/LiverScenario.h"

namespace bcassim {

class LiverCommand {
 public:
  // Registers `liver prepare` and `liver run` on `app`.
  explicit LiverCommand(CLI::App& app);
  bool parsed() const { return liver_->parsed(); }
  // Runs the parsed subcommand; returns the exit code. Throws InputError, NumericalError.
  int run() const;

 private:
  int prepare() const;
  int runAll() const;

  CLI::App* liver_ = nullptr;
  CLI::App* prepare_ = nullptr;
  CLI::App* run_ = nullptr;
  std::string surface_, outDir_ = "out/liver";
  LiverScenarioOptions options_;
  bool quiet_ = false, noPlots_ = false, noPicture_ = false, resume_ = false;
};

}  // namespace bcassim
