// Running another program: stock colmap from a library (no shell, so paths
// with spaces or quotes reach it unchanged, and its output goes to a log
// file instead of mixing into ours), and shell command lines from tests
// (their output captured). One spawn underneath (posix_spawn); exit codes
// are the program's, or 128 + the signal number if it was killed.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace uw {

// Runs argv[0] (looked up on PATH when it has no '/') with the arguments
// argv[1...], its stdout and stderr appended to log_path, and waits for it.
// Returns its exit code. Throws uw::Error when argv is empty, the log cannot
// be opened or the program cannot be started (not installed), naming the
// program.
int RunProgram(const std::vector<std::string>& argv,
               const std::filesystem::path& log_path);

struct ProcessResult {
  int exit_code = -1;
  std::string output;  // stdout, plus stderr when requested
};

// Runs a shell command line (argv {"/bin/sh", "-c", command}: pipes,
// redirections and `cd dir &&` work) and waits for it, capturing its
// stdout. With merge_stderr, stderr is captured too, interleaved as written;
// otherwise it is discarded so that logs do not mix into the result. Throws
// uw::Error when the shell cannot be started.
ProcessResult RunProcess(const std::string& command, bool merge_stderr);

// The last max_lines lines of a text file (for error messages that quote a
// failed program's log); empty if it cannot be read.
std::string TailOfFile(const std::filesystem::path& path, int max_lines);

}  // namespace uw
