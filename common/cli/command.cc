#include "common/cli/command.h"

#include <algorithm>
#include <cstring>
#include <iostream>
#include <set>

#include "common/util/error.h"

namespace uw {
namespace {

template <typename Command>
void PrintUsage(const std::string& usage, const std::vector<Command>& commands,
                std::ostream& out) {
  size_t width = 0;
  for (const Command& command : commands) {
    width = std::max(width, std::string(command.name).size());
  }
  out << usage << "\nCommands:\n";
  for (const Command& command : commands) {
    const std::string name = command.name;
    out << "  " << name << std::string(width + 4 - name.size(), ' ')
        << command.summary << "\n";
  }
}

bool AsksForHelp(int argc, char** argv) {
  return argc < 2 || std::strcmp(argv[1], "-h") == 0 ||
         std::strcmp(argv[1], "--help") == 0 ||
         std::strcmp(argv[1], "help") == 0;
}

template <typename Command>
int Dispatch(const std::string& usage, const std::vector<Command>& commands,
             int argc, char** argv,
             const std::function<int(const Command&, int, char**)>& run) {
  if (AsksForHelp(argc, argv)) {
    PrintUsage(usage, commands, std::cout);
    return argc < 2 ? 1 : 0;
  }
  for (const Command& command : commands) {
    if (command.name == std::string(argv[1])) {
      return run(command, argc - 1, argv + 1);
    }
  }
  std::cerr << "ERROR: unknown command '" << argv[1] << "'\n\n";
  PrintUsage(usage, commands, std::cerr);
  return 1;
}

}  // namespace

int RunCommand(CLI::App& app, int argc, char** argv,
               const std::function<void()>& body) {
  try {
    try {
      app.parse(argc, argv);
    } catch (const CLI::ParseError& error) {
      return app.exit(error) == 0 ? 0 : 2;
    } catch (const std::exception&) {
      // CLI11 runs the flags' readers before it answers --help: a value a
      // reader refuses must not hide the help that was asked for.
      if (app.get_help_ptr() != nullptr && app.get_help_ptr()->count() > 0) {
        return app.exit(CLI::CallForHelp());
      }
      throw;
    }
    body();
  } catch (const std::exception& error) {
    // A flag's own reader (common/cli/flags.h) throws uw::Error while
    // parsing, like any bad input.
    std::cerr << "ERROR: " << error.what() << std::endl;
    return 1;
  }
  return 0;
}

int DispatchSubcommand(const std::string& program, const std::string& usage,
                       const std::vector<Subcommand>& commands, int argc,
                       char** argv) {
  return Dispatch<Subcommand>(
      usage, commands, argc, argv,
      [&](const Subcommand& command, int command_argc, char** command_argv) {
        if (command.legacy_run) {
          return command.legacy_run(command_argc, command_argv);
        }
        CommandLine cli(program + " " + command.name, command.description);
        const std::function<void()> run = command.define(&cli);
        return RunCommand(cli.app(), command_argc, command_argv, run);
      });
}

int DispatchSubcommand(const std::string& usage,
                       const std::vector<LegacySubcommand>& commands, int argc,
                       char** argv) {
  return Dispatch<LegacySubcommand>(usage, commands, argc, argv,
                                    [](const LegacySubcommand& command,
                                       int command_argc, char** command_argv) {
                                      return command.run(command_argc,
                                                         command_argv);
                                    });
}

bool ParseColmapBool(const std::string& value, const std::string& flag) {
  if (value == "1" || value == "true") return true;
  if (value == "0" || value == "false") return false;
  throw ErrorAt("--", flag, ": expected 0 or 1, got '", value, "'");
}

std::vector<std::string> UnboundFlags(const Subcommand& command) {
  if (command.legacy_run) return {"(all: it parses its own flags)"};
  CommandLine cli(command.name, command.description);
  command.define(&cli);
  std::vector<std::string> unbound;
  std::set<std::pair<const void*, size_t>> fields;
  for (const CLI::Option* option : cli.app().get_options()) {
    if (option == cli.app().get_help_ptr()) continue;
    // A flag may write several fields (AddIntegers); each must be its own.
    bool bound = false;
    bool own_fields = true;
    for (const CommandLine::Binding& binding : cli.Bindings()) {
      if (binding.option != option) continue;
      bound = true;
      own_fields = own_fields &&
                   cli.WritesIntoOptions(binding.field, binding.size) &&
                   fields.insert({binding.field, binding.size}).second;
    }
    if (!bound || !own_fields) unbound.push_back(option->get_name());
  }
  return unbound;
}

}  // namespace uw
