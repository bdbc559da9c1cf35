// Shared helpers of the tests: a fresh temporary directory per test, writing and reading
// small text files, and running the bcassim executable as a subprocess.
#pragma once
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace bcassim::test {

// The directory holding this test process's temporary files.
inline std::filesystem::path processTempRoot() {
  return std::filesystem::temp_directory_path() / ("bcassim_test_" + std::to_string(getpid()));
}

// A directory unique to the running test, emptied at creation.
inline std::filesystem::path freshDir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::filesystem::path dir =
      processTempRoot() / (std::string(info->test_suite_name()) + "_" + info->name());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

inline void writeText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path) << text;
}

inline std::string readText(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Whether `text` contains `what`.
inline bool contains(const std::string& text, const std::string& what) {
  return text.find(what) != std::string::npos;
}

inline int countLines(const std::string& text) {
  int n = 0;
  for (char c : text) n += c == '\n';
  return n;
}

inline int countOccurrences(const std::string& text, const std::string& what) {
  int n = 0;
  for (size_t pos = text.find(what); pos != std::string::npos; pos = text.find(what, pos + 1)) ++n;
  return n;
}

// Mean of `parameter` at `step` in an assimilation run's estimates.csv
// (step,time_s,parameter,mean,stddev); a test failure and NaN when there is none.
inline double estimateAt(const std::filesystem::path& csv, const std::string& parameter, int step) {
  std::ifstream in(csv);
  std::string line;
  const std::string prefix = std::to_string(step) + ",";
  while (std::getline(in, line)) {
    if (line.rfind(prefix, 0) != 0) continue;
    std::vector<std::string> f;
    std::stringstream s(line);
    for (std::string x; std::getline(s, x, ',');) f.push_back(x);
    if (f.size() == 5 && f[2] == parameter) return std::stod(f[3]);
  }
  ADD_FAILURE() << "no estimate of " << parameter << " at step " << step << " in " << csv;
  return std::nan("");
}

struct CliResult {
  int exitCode = -1;
  std::string out, err;
};

// Runs `bcassim <args>` from `dir` (args are passed through the shell as written).
inline CliResult runBcassim(const std::filesystem::path& dir, const std::string& args) {
  const std::string cmd =
      "cd '" + dir.string() + "' && '" + BCASSIM_BINARY + "' " + args + " > cli.out 2> cli.err";
  const int status = std::system(cmd.c_str());
  CliResult r;
  r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = readText(dir / "cli.out");
  r.err = readText(dir / "cli.err");
  return r;
}

// Writes `yaml` as scene.yaml in a fresh directory, runs `bcassim simulate` on it and expects
// exit code 2 with exactly "bcassim: error: <message>" on stderr and nothing on stdout.
inline void expectSceneInputError(const std::string& yaml, const std::string& message) {
  const std::filesystem::path dir = freshDir();
  writeText(dir / "scene.yaml", yaml);
  const CliResult r = runBcassim(dir, "simulate scene.yaml --out out --quiet");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_EQ(r.err, "bcassim: error: " + message + "\n");
  EXPECT_EQ(r.out, "");
}

}  // namespace bcassim::test
