// The options several commands have, declared here once so that their names and help read the
// same everywhere: --out, --resume, -q/--quiet, --threads, --no-plots, --scale.
#pragma once
#include <string>

namespace CLI {
class App;
class Option;
}  // namespace CLI

namespace bcassim {

// -o,--out DIR; dir holds the command's default, which --help shows.
CLI::Option* addOutOption(CLI::App& app, std::string& dir);

// --resume; continuesFrom completes "Continue a stopped run in --out from ...".
CLI::Option* addResumeFlag(CLI::App& app, bool& resume, const std::string& continuesFrom);

// -q,--quiet: no progress bars on stderr; what a command prints on stdout stays.
CLI::Option* addQuietFlag(CLI::App& app, bool& quiet);

// --threads N, N >= 1 (anything else is an argument error naming --threads). what: what runs on
// them and the default when the option is absent, e.g. "the sigma points' forecasts (default:
// ...)". With captureDefault the current value of threads is shown as the default.
CLI::Option* addThreadsOption(CLI::App& app, int& threads, const std::string& what,
                              bool captureDefault);

// --no-plots: the PNG plots drawn by a Python script after the run are skipped.
CLI::Option* addNoPlotsFlag(CLI::App& app, bool& noPlots);

// Refuses anything but a number >= 0 for `option` with one line naming it ("--x: expected a
// number >= 0, got '-1'"). Returns the option.
CLI::Option* checkNonNegative(CLI::Option* option);

// The same for a number > 0 ("--x: expected a number > 0, got '0'").
CLI::Option* checkPositive(CLI::Option* option);

// --scale: metres per unit of a surface file (the shared livers are in mm).
CLI::Option* addScaleOption(CLI::App& app, double& metresPerUnit);

}  // namespace bcassim
