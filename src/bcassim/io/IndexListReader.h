// Reading a list of node or vertex ids (0-based) from a file, so that a scene can name a zone
// by file instead of inline: .csv, .txt (whitespace separated) or .npy.
#pragma once
#include <string>
#include <vector>

namespace bcassim {

// Ids in file order, duplicates kept. .csv: comma-separated ids, any number per line, an
// optional first line without numbers (a header) is skipped. .txt: whitespace-separated ids,
// any number per line. Both skip blank lines and '#' comments (to the end of a line). .npy: an
// integer array (or a float array of whole numbers) of shape (N,), (N, 1) or (1, N). Every id
// is a non-negative integer below 2^31, and there is at least one. Throws InputError naming the
// file and the line or entry, e.g. "ids.txt:3: expected a non-negative integer id, got '-1'".
std::vector<int> readIndexList(const std::string& path);

}  // namespace bcassim
