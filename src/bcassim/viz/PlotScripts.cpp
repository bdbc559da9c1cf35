#include "bcassim/viz/PlotScripts.h"

#include <fmt/format.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>

namespace bcassim {
namespace {

std::string shellQuote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

}  // namespace

std::string findScript(const std::string& name) {
  std::error_code ec;
  if (const char* env = std::getenv("BCASSIM_SCRIPTS_DIR")) {
    const std::filesystem::path p = std::filesystem::path(env) / name;
    return std::filesystem::is_regular_file(p, ec) ? p.string() : std::string();
  }
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) return {};
  const std::filesystem::path root = exe.parent_path().parent_path();
  for (const auto& candidate : {root / "scripts" / name, root / "share" / "bcassim" / name})
    if (std::filesystem::is_regular_file(candidate, ec)) return candidate.string();
  return {};
}

std::string runPlotScript(const std::string& name, const std::vector<std::string>& args) {
  const std::string script = findScript(name);
  if (script.empty()) return fmt::format("scripts/{} not found (set BCASSIM_SCRIPTS_DIR)", name);
  // The first python3 on PATH may be a private one (pyenv, venv) without the Debian package.
  std::string python;
  for (const char* candidate : {"python3", "/usr/bin/python3"}) {
    const std::string probe = std::string(candidate) + " -c 'import matplotlib' > /dev/null 2>&1";
    if (std::system(probe.c_str()) == 0) {
      python = candidate;
      break;
    }
  }
  if (python.empty())
    return "python3 with matplotlib not found (apt-get install python3-matplotlib)";
  std::fflush(stdout);  // the script's own lines come after what the caller printed
  std::string cmd = python + ' ' + shellQuote(script);
  for (const std::string& a : args) {
    cmd += ' ';
    cmd += shellQuote(a);
  }
  if (std::system(cmd.c_str()) != 0) return fmt::format("{} failed", cmd);
  return {};
}

}  // namespace bcassim
