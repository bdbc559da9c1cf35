// Cutting a per-step CSV file back to a point in the run, so that a resumed run appends to it
// without duplicate or stale rows.
#pragma once
#include <fstream>
#include <optional>
#include <string>

namespace bcassim {

// Keeps the lines of `path` whose first field is not a number (the header, comments) and the
// rows whose first field (a time or a step) is at most `limit`; drops the others, and a last line
// cut short by a crash. Rewrites the file in place (through a temporary and a rename). Throws
// InputError if it cannot be read or written.
void keepCsvRowsUpTo(const std::string& path, double limit);

// A per-step CSV file of a run: new (parent folder created) with its header line, or, resuming
// (resumeUpTo set), cut back by keepCsvRowsUpTo and opened for appending. Throws InputError.
std::ofstream openStepCsv(const std::string& path, const std::string& header,
                          std::optional<double> resumeUpTo);

}  // namespace bcassim
