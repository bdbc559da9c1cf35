// The bcassim executable's one place of wiring: the list of every command, the command tree made
// from their paths, the parse, the run of the one command parsed, and errors as exit codes.
#include "bcassim/cli/Cli.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <map>
#include <memory>
#include <new>
#include <string>
#include <vector>

#include "bcassim/Error.h"
#include "bcassim/cli/Commands.h"

#ifndef BCASSIM_VERSION
#define BCASSIM_VERSION "0.1.0"
#endif

namespace bcassim {

namespace {

// Exit codes: 0 success, 1 internal error, 2 bad input (file, scene, arguments), 3 numerical
// failure during a run, 4 an output that could not be written.
constexpr int kExitInternal = 1;
constexpr int kExitInput = 2;
constexpr int kExitNumerical = 3;
constexpr int kExitOutput = 4;

// Every command of the executable, in the order --help lists them.
std::vector<std::unique_ptr<Command>> allCommands() {
  std::vector<std::unique_ptr<Command>> commands;
  commands.push_back(makeSimulateCommand());
  commands.push_back(makeAssimilateCommand());
  commands.push_back(makeValidateCommand());
  commands.push_back(makeServeCommand());
  commands.push_back(makeReplayCommand());
  commands.push_back(makeMeshInfoCommand());
  commands.push_back(makeMeshTetraCommand());
  commands.push_back(makeTrackCommand());
  commands.push_back(makeRegisterCommand());
  commands.push_back(makeAtlasDistanceCommand());
  commands.push_back(makeAtlasRegisterCommand());
  commands.push_back(makeAtlasBuildCommand());
  commands.push_back(makeAtlasTransferCommand());
  commands.push_back(makeAtlasLooCommand());
  commands.push_back(makeLigamentFitCommand());
  commands.push_back(makeLigamentSpringsCommand());
  commands.push_back(makeLiverPrepareCommand());
  commands.push_back(makeLiverRunCommand());
  commands.push_back(makeLiverTrackedCommand());
  return commands;
}

// The one-line help of the commands that only group others.
const std::map<std::string, std::string> kGroupDescriptions = {
    {"mesh", "Mesh tools"},
    {"atlas", "Statistical atlas of ligament curves (LDDMM registration, thesis §4.3, §5.2)"},
    {"ligament", "Ligament properties from tissue measurements (thesis §2.3.4, §4.4)"},
    {"liver", "The liver experiments of thesis §5.1 and §5.3 from a CT surface"}};

// The error on one line, whatever the exception text holds.
void printError(const std::string& what) {
  std::string line = what;
  for (char& c : line)
    if (c == '\n' || c == '\r') c = ' ';
  fmt::print(stderr, "bcassim: error: {}\n", line);
}

// The subcommand `name` of parent, made (needing one subcommand of its own) if not there yet.
CLI::App& groupOf(CLI::App& parent, const std::string& name) {
  const std::vector<CLI::App*> found =
      parent.get_subcommands([&](CLI::App* sub) { return sub->get_name() == name; });
  if (!found.empty()) return *found.front();
  CLI::App* group = parent.add_subcommand(name, kGroupDescriptions.at(name));
  group->require_subcommand(1);
  return *group;
}

// The leaf subcommand of command, with its groups above it, its options declared on it.
CLI::App* addCommand(CLI::App& app, Command& command) {
  const std::vector<std::string>& path = command.path();
  CLI::App* parent = &app;
  for (size_t i = 0; i + 1 < path.size(); ++i) parent = &groupOf(*parent, path[i]);
  CLI::App* leaf = parent->add_subcommand(path.back(), command.description());
  command.declare(*leaf);
  return leaf;
}

int run(int argc, char** argv) {
  CLI::App app{"bcassim: boundary conditions of organ models by Kalman filtering", "bcassim"};
  app.set_version_flag("--version", std::string("bcassim ") + BCASSIM_VERSION);
  app.require_subcommand(1);

  const std::vector<std::unique_ptr<Command>> commands = allCommands();
  std::vector<CLI::App*> leaves;
  leaves.reserve(commands.size());
  for (const std::unique_ptr<Command>& command : commands)
    leaves.push_back(addCommand(app, *command));

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    printError(std::string(e.what()) + " (see 'bcassim --help')");
    return kExitInput;
  }
  for (size_t i = 0; i < commands.size(); ++i)
    if (leaves[i]->parsed()) return commands[i]->run();
  printError("internal error: no command was parsed");
  return kExitInternal;
}

}  // namespace

int runCli(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const OutputError& e) {
    printError(e.what());
    return kExitOutput;
  } catch (const InputError& e) {
    printError(e.what());
    return kExitInput;
  } catch (const NumericalError& e) {
    printError(e.what());
    return kExitNumerical;
  } catch (const std::filesystem::filesystem_error& e) {
    printError(e.what());
    return kExitInput;
  } catch (const std::bad_alloc&) {
    printError("out of memory");
    return kExitInternal;
  } catch (const std::exception& e) {
    printError(std::string("internal error: ") + e.what());
    return kExitInternal;
  } catch (...) {
    printError("internal error: unknown exception");
    return kExitInternal;
  }
}

}  // namespace bcassim
