// Internal file-system helpers of the io module, with one-line InputErrors naming the path.
#pragma once
#include <string>
#include <string_view>

namespace bcassim::io {

// Throws InputError "<path>: cannot open file" unless `path` is an existing regular file.
void requireReadableFile(const std::string& path);

// Creates the parent directory of `path` if missing; throws InputError when it cannot.
void createParentDirectory(const std::string& path);

// The content of a file mapped read-only into memory (no copy, no zero-filled buffer), for the
// readers that parse whole files. Throws InputError "<path>: cannot open file" when it is not a
// readable regular file.
class MappedFile {
 public:
  explicit MappedFile(const std::string& path);
  ~MappedFile();
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;
  std::string_view bytes() const { return {data_, size_}; }

 private:
  const char* data_ = "";
  size_t size_ = 0;
  bool mapped_ = false;
};

// The system's text for an errno value ("No space left on device"), for the message of a failed
// open, write, flush, close or rename; "unknown cause" for 0. Take errno right after the failing
// call: anything else may change it.
std::string systemErrorText(int error);

// Throws InputError "<path>: cannot write file (<errno's text>)", e.g. "(No space left on
// device)", for a failed open, write, flush or close; call it right after the failing call.
[[noreturn]] void throwWriteError(const std::string& path);

// Lower-case extension with its dot, e.g. ".vtu"; empty when none.
std::string lowerExtension(const std::string& path);

}  // namespace bcassim::io
