// The commands of the bcassim executable, one maker each; the classes live in the .cpp file
// named beside each maker, and Cli.cpp lists them all in one place.
#pragma once
#include <memory>

#include "bcassim/cli/Command.h"

namespace bcassim {

// SimulateCommand.cpp
std::unique_ptr<Command> makeSimulateCommand();
// AssimilateCommand.cpp
std::unique_ptr<Command> makeAssimilateCommand();
std::unique_ptr<Command> makeValidateCommand();
// MeshInfoCommand.cpp
std::unique_ptr<Command> makeMeshInfoCommand();
std::unique_ptr<Command> makeMeshTetraCommand();
// LiverCommands.cpp
std::unique_ptr<Command> makeLiverPrepareCommand();
std::unique_ptr<Command> makeLiverRunCommand();
std::unique_ptr<Command> makeLiverTrackedCommand();
// TrackingCommands.cpp
std::unique_ptr<Command> makeTrackCommand();
std::unique_ptr<Command> makeRegisterCommand();
// StreamCommands.cpp
std::unique_ptr<Command> makeServeCommand();
std::unique_ptr<Command> makeReplayCommand();
// LigamentCommands.cpp
std::unique_ptr<Command> makeLigamentFitCommand();
std::unique_ptr<Command> makeLigamentSpringsCommand();
// AtlasCommands.cpp
std::unique_ptr<Command> makeAtlasDistanceCommand();
std::unique_ptr<Command> makeAtlasRegisterCommand();
std::unique_ptr<Command> makeAtlasBuildCommand();
std::unique_ptr<Command> makeAtlasTransferCommand();
std::unique_ptr<Command> makeAtlasLooCommand();

}  // namespace bcassim
