// A scene's assimilation served to navigation software over OpenIGTLink (thesis §4.6, §5.4):
// frames from the server's clients become the filter's observations, and every frame's hidden
// points and surface go back to every client. Synchronous (the filter's step in the loop) or
// asynchronous (a real-time model answers at once with the latest analysis while the filter runs
// behind on its own thread, through live/LiveEngine).
#pragma once
#include <atomic>
#include <functional>
#include <string>
#include <vector>

#include "bcassim/navigation/ServeOptions.h"
#include "bcassim/run/AssimilationRunner.h"
#include "bcassim/scene/Scene.h"
#include "bcassim/stream/IgtlServer.h"

namespace bcassim {

struct ServeReport {
  AssimilationResult assimilation;  // the filter's run (files in options.outDir)
  long framesReceived = 0;
  long framesRefused = 0;          // malformed, late or twice (each logged)
  long framesSkippedByFilter = 0;  // asynchronous: left out on purpose when it fell behind
  std::vector<double> latencyMs;   // per answered frame: its arrival to its answer sent
  std::vector<long> lagFrames;     // asynchronous: per answered frame, the analysis' lag
  std::vector<double> realTimeMs;  // asynchronous: per frame, the real-time step's wall time
  double framePeriodS = 0.0;       // median interval between frame arrivals, s
};

// Opens the server (listening, its address announced) and returns it; called once, when the
// filter and the real-time model are set up, so that no frame waits for the set-up.
using OpenServer = std::function<IgtlServer&()>;

// Serves until the scene's last step, an interrupt (`interrupted` set), or options.idleTimeout.
// `log` gets one line per event (from two threads, never at once). Throws InputError,
// NumericalError (a failed filter or real-time step, naming it), and what openServer throws.
ServeReport serveScene(const Scene& scene, const ServeOptions& options,
                       const OpenServer& openServer, const std::atomic<bool>& interrupted,
                       const IgtlServer::Log& log);

}  // namespace bcassim
