// Running another program (stock colmap) from a library: no shell, so paths
// with spaces or quotes reach it unchanged, and its output goes to a log
// file instead of mixing into ours.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace uw {

// Runs argv[0] (looked up on PATH when it has no '/') with the arguments
// argv[1...], its stdout and stderr appended to log_path, and waits for it.
// Returns its exit code (128 + signal number if it was killed). Throws
// uw::Error when argv is empty, the log cannot be opened or the program
// cannot be started (not installed), naming the program.
int RunProgram(const std::vector<std::string>& argv,
               const std::filesystem::path& log_path);

// The last max_lines lines of a text file (for error messages that quote a
// failed program's log); empty if it cannot be read.
std::string TailOfFile(const std::filesystem::path& path, int max_lines);

}  // namespace uw
