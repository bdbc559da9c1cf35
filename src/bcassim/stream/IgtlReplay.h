// Sends recorded marker tracks to an OpenIGTLink server frame by frame at a fixed rate, as a
// camera would (one POINT message per frame, its time stamp the track time), and times the
// server's answers (the hidden points message with the same stamp).
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "bcassim/io/CsvTracks.h"

namespace bcassim {

struct ReplayOptions {
  std::string host = "127.0.0.1";
  int port = 18944;
  double rate = 30.0;              // frames per second (> 0)
  std::string device = "Markers";  // the POINT messages' device name
  std::string answerDevice = "bcassim_hidden";
  // After the last frame: how long to wait for answers before closing, s (the server closing the
  // connection ends the wait at once).
  double waitSeconds = 5.0;
};

struct ReplayReport {
  long sent = 0;                    // frames
  double seconds = 0.0;             // from the first frame sent to the last
  long answers = 0;                 // answer messages received
  std::vector<double> roundTripMs;  // per answered frame: frame sent -> its answer received
};

// Throws InputError when it cannot connect or the server's stream is not OpenIGTLink.
ReplayReport replayTracks(const MarkerTracks& tracks, const ReplayOptions& options);

}  // namespace bcassim
