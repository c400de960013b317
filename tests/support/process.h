// What tests that run programs need beyond common/util/subprocess.h (which
// runs them): quoting for the shell command lines they build, and a fresh
// directory per test for their output.
#pragma once

#include <filesystem>
#include <string>

namespace uw::testing {

// Quotes a path for /bin/sh.
std::string Quoted(const std::filesystem::path& path);

// A fresh, empty directory for the running test under the system temp dir.
std::filesystem::path FreshTestDir(const std::string& suite);

}  // namespace uw::testing
