// One subcommand of the bcassim executable: where it sits in the command tree, a one-line
// description, the options it declares and its run(). Cli.cpp holds the list of all of them.
#pragma once
#include <string>
#include <utility>
#include <vector>

namespace CLI {
class App;
}

namespace bcassim {

class Command {
 public:
  // path: the words that call it, e.g. {"simulate"} or {"atlas", "build"}; the parents
  // ("atlas") are made by Cli.cpp. description: one line for --help.
  Command(std::vector<std::string> path, std::string description)
      : path_(std::move(path)), description_(std::move(description)) {}
  virtual ~Command() = default;
  Command(const Command&) = delete;
  Command& operator=(const Command&) = delete;

  const std::vector<std::string>& path() const { return path_; }
  const std::string& description() const { return description_; }

  // Declares the command's arguments and options on its own subcommand, bound to its members
  // (shared ones through SharedOptions.h).
  virtual void declare(CLI::App& app) = 0;
  // Runs the command once its options are parsed and prints its results on stdout. Returns the
  // exit code; throws InputError (bad input) or NumericalError (a failed solve).
  virtual int run() = 0;

 private:
  std::vector<std::string> path_;
  std::string description_;
};

}  // namespace bcassim
