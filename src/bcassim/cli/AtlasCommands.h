// The `bcassim atlas` commands (thesis §4.3, §5.2): distance, register, build, transfer, loo.
#pragma once

namespace CLI {
class App;
}

namespace bcassim {

// Adds `atlas` and its subcommands to app; each runs from its CLI11 callback, ends the parse
// with exit code 0 on success and throws InputError / NumericalError on failure.
void addAtlasCommands(CLI::App& app);

}  // namespace bcassim
