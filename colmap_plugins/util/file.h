// Writing files so that an interrupted or failed run never leaves a half
// written output behind (DESIGN.md §4): content goes to a temporary sibling
// and is renamed into place only once every file of a set is complete.
#pragma once

#include <filesystem>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace uw {

// One output file: its final path and the function that writes its content.
struct PendingFile {
  std::filesystem::path path;
  std::function<void(std::ostream&)> write;
};

// Writes every file to "<path>.tmp-<pid>" first; if any writer throws or a
// stream fails, all temporaries are removed, no final file is touched and
// the error propagates. Otherwise the temporaries are renamed into place.
// Parent directories are created as needed.
void WriteFilesAtomically(const std::vector<PendingFile>& files, bool binary);

// Reads a whole file; throws uw::Error naming the path if it cannot.
std::string ReadFileToString(const std::filesystem::path& path);

}  // namespace uw
