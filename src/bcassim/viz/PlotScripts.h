// Running the project's python3-matplotlib scripts (scripts/*.py) that draw PNG plots from the
// CSV files a command wrote. Plots are a convenience: a missing Python never fails a run.
#pragma once
#include <string>
#include <vector>

namespace bcassim {

// Path of scripts/<name>: $BCASSIM_SCRIPTS_DIR/<name>, else beside the executable's parent (a
// build directory in the source tree) or in its share/bcassim (an installed tree); empty if none.
std::string findScript(const std::string& name);

// Runs `python3 scripts/<name> args...` with a python3 that has matplotlib. Returns an empty
// string when the script ran and succeeded, else one line saying why not (for the caller to show).
std::string runPlotScript(const std::string& name, const std::vector<std::string>& args);

}  // namespace bcassim
