// Off-screen VTK picture of a liver run (`bcassim liver run`): the estimated liver at the frame of
// largest deformation coloured by its distance to the truth, the ligament springs, the observed
// markers, and each tumour with its 95 % uncertainty sphere beside its true position.
#pragma once
#include <string>

namespace bcassim {

// Reads the files of a liver run directory and writes `png`. Returns an empty string on success,
// else why no picture was made (no X display, missing files); never throws for a missing display,
// because VTK 9.1 on Debian renders through X (run under xvfb-run on a headless machine).
std::string renderLiverPicture(const std::string& runDir, const std::string& png);

}  // namespace bcassim
