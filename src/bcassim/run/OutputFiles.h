// Whole output files of the runners (parameters.csv, summaries) and flushing the per-step ones:
// opened with their folder made, a one-line InputError naming the file when the disk refuses.
#pragma once
#include <filesystem>
#include <fstream>

namespace bcassim {

// Creates the parent folder if missing and truncates `path`. Throws InputError "<path>: cannot
// write file (<errno's text>)".
std::ofstream openForWriting(const std::filesystem::path& path);

// Flushes `out` (written to `path`); throws InputError "<path>: cannot write file (<errno's text>)"
// if it failed.
void flushOrThrow(std::ofstream& out, const std::filesystem::path& path);

// Creates the run's output folder; throws OutputError "<dir>: cannot create directory (why)".
void createOutputDirectory(const std::filesystem::path& dir);

}  // namespace bcassim
