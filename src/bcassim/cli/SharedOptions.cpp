#include "bcassim/cli/SharedOptions.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <charconv>
#include <cmath>
#include <string>
#include <system_error>

namespace bcassim {

CLI::Option* addOutOption(CLI::App& app, std::string& dir) {
  return app.add_option("-o,--out", dir, "Output directory (created if missing)")
      ->capture_default_str();
}

CLI::Option* addResumeFlag(CLI::App& app, bool& resume, const std::string& continuesFrom) {
  return app.add_flag("--resume", resume, "Continue a stopped run in --out from " + continuesFrom);
}

CLI::Option* addQuietFlag(CLI::App& app, bool& quiet) {
  return app.add_flag("-q,--quiet", quiet, "No progress bars on stderr (results still printed)");
}

CLI::Option* addThreadsOption(CLI::App& app, int& threads, const std::string& what,
                              bool captureDefault) {
  const CLI::Validator atLeastOne(
      [](const std::string& text) -> std::string {
        int n = 0;
        const char* end = text.data() + text.size();
        const auto [last, error] = std::from_chars(text.data(), end, n);
        if (error != std::errc() || last != end || n < 1)
          return fmt::format("expected a whole number of threads >= 1, got '{}'", text);
        return "";
      },
      "POSITIVE");
  CLI::Option* o = app.add_option("--threads", threads, "Threads for " + what)->check(atLeastOne);
  if (captureDefault) o->capture_default_str();
  return o;
}

namespace {

// A number that `accepts` takes; `expected` completes the refusal "expected a number ...".
CLI::Validator numberValidator(bool (*accepts)(double), const char* expected, const char* name) {
  return CLI::Validator(
      [accepts, expected](const std::string& text) -> std::string {
        double v = 0.0;
        const char* end = text.data() + text.size();
        const auto [last, error] = std::from_chars(text.data(), end, v);
        if (error != std::errc() || last != end || !accepts(v))
          return fmt::format("expected a number {}, got '{}'", expected, text);
        return "";
      },
      name);
}

}  // namespace

CLI::Option* checkNonNegative(CLI::Option* option) {
  return option->check(numberValidator([](double v) { return v >= 0.0; }, ">= 0", "NONNEGATIVE"));
}

CLI::Option* checkPositive(CLI::Option* option) {
  return option->check(
      numberValidator([](double v) { return v > 0.0 && std::isfinite(v); }, "> 0", "POSITIVE"));
}

CLI::Option* addNoPlotsFlag(CLI::App& app, bool& noPlots) {
  return app.add_flag("--no-plots", noPlots, "Do not draw the PNG plots");
}

CLI::Option* addScaleOption(CLI::App& app, double& metresPerUnit) {
  return app
      .add_option("--scale", metresPerUnit,
                  "Metres per unit of the surface file (1e-3: millimetres, as the shared livers)")
      ->capture_default_str();
}

}  // namespace bcassim
