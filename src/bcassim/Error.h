// Typed errors of the library. The library never prints: it throws these and the CLI shows
// what() as one line, e.g. "mesh.msh:42: expected 4 node indices, got 3".
#pragma once
#include <stdexcept>
#include <string>

namespace bcassim {
// Bad user input: a file, a scene key, a value. The message names the source (file, line or key)
// and what was expected, on one line.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// An output that could not be written (a full disk, no permission, a missing device): the message
// names the file and the system's reason. An InputError too, so that code handling bad input
// handles it; the CLI tells them apart by exit code (4, not 2).
class OutputError : public InputError {
 public:
  using InputError::InputError;
};

// A numerical failure the caller may handle (diverged solve, inverted element during a step).
class NumericalError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};
}  // namespace bcassim
