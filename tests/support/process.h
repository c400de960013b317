// Running programs (stock colmap, our CLIs) from integration tests.
#pragma once

#include <filesystem>
#include <string>

namespace uw::testing {

struct ProcessResult {
  int exit_code = -1;
  std::string output;  // stdout, plus stderr when requested
};

// Runs `command` through /bin/sh. With merge_stderr, stderr is captured
// too; otherwise it is discarded so that logs do not mix into the result.
ProcessResult RunProcess(const std::string& command, bool merge_stderr);

// Quotes a path for /bin/sh.
std::string Quoted(const std::filesystem::path& path);

// A fresh, empty directory for the running test under the system temp dir.
std::filesystem::path FreshTestDir(const std::string& suite);

}  // namespace uw::testing
