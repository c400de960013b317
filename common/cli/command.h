// The plumbing every uwmetric program shares: a program is a table of
// commands (`uwcolmap bundle_adjuster`, `laserscale detect`, ...), a command
// is an options struct whose fields its flags fill (common/cli/flags.h), a
// Check() of the whole, and a function that runs a controller and writes
// the results; one place turns a failure into a message and an exit code.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "common/cli/flags.h"

namespace uw {

// One command of a program.
struct Subcommand {
  std::string name;
  std::string summary;      // one line, for the program's command list
  std::string description;  // --help's text, ending with an example
  // Declares the command's flags on `cli`, bound to an options object that
  // it owns, and returns what runs once they are parsed.
  std::function<std::function<void()>(CommandLine* cli)> define;
};

// A command whose flags `add_flags` binds to the fields of an `Options`;
// once they are parsed, `options.Check()` validates the whole (every rule
// between fields lives there) and `run` does the job. `run` may print: only
// executables do.
template <typename Options>
Subcommand MakeSubcommand(std::string name, std::string summary,
                          std::string description,
                          void (*add_flags)(CommandLine*, Options*),
                          void (*run)(const Options&)) {
  return {std::move(name), std::move(summary), std::move(description),
          [add_flags, run](CommandLine* cli) -> std::function<void()> {
            auto options = std::make_shared<Options>();
            cli->DeclareOptions(options.get(), sizeof(Options));
            add_flags(cli, options.get());
            return [options, run] {
              options->Check();
              run(*options);
            };
          }};
}

// Parses the flags and runs `body`; exit codes: 0 success, 1 bad input or
// any other failure (printed as "ERROR: ..." on stderr), 2 flags CLI11
// cannot parse (unknown flag, missing required flag, a number that is not
// one). --help prints the flags with their defaults and exits 0.
int RunCommand(CLI::App& app, int argc, char** argv,
               const std::function<void()>& body);

// Like `colmap`: argv[1] names the command, which gets the rest. With no
// argument, -h, --help or help, prints `usage` and the command list (exit 1
// without an argument, else 0); an unknown name is an error (exit 1).
// `program` prefixes each command's name in its --help ("uwcolmap").
int DispatchSubcommand(const std::string& program, const std::string& usage,
                       const std::vector<Subcommand>& commands, int argc,
                       char** argv);

// The flags of `command` that write no field of its options (or the same
// bytes as another flag), by name: empty when every flag is bound 1:1.
std::vector<std::string> UnboundFlags(const Subcommand& command);

}  // namespace uw
