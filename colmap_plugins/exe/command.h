// Shared plumbing of uwcolmap commands: COLMAP-style flags parsed with
// CLI11, and one place that turns a uw::Error into a message and exit code.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace uw {

// Runs `body` and maps failures to exit codes: 0 success, 1 uw::Error or
// other failure (message printed as "ERROR: ..." on stderr), 2 bad flags.
int RunCommand(CLI::App& app, int argc, char** argv,
               const std::function<void()>& body);

// One command of a multi-command program (`uwcolmap`, `laserscale`).
struct Subcommand {
  const char* name;
  int (*run)(int argc, char** argv);
  const char* summary;
};

// Like `colmap`: argv[1] names the command, which gets the rest. With no
// argument, -h, --help or help, prints `usage` and the command list (exit 1
// without an argument, else 0); an unknown name is an error (exit 1).
int DispatchSubcommand(const std::string& usage,
                       const std::vector<Subcommand>& commands, int argc,
                       char** argv);

// COLMAP writes booleans on its command line as 0/1 (also true/false).
bool ParseColmapBool(const std::string& value, const std::string& flag);

}  // namespace uw
