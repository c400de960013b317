#include "common/cli/command.h"

#include <algorithm>
#include <cstring>
#include <iostream>
#include <set>

namespace uw {
namespace {

void PrintUsage(const std::string& usage,
                const std::vector<Subcommand>& commands, std::ostream& out) {
  size_t width = 0;
  for (const Subcommand& command : commands) {
    width = std::max(width, command.name.size());
  }
  out << usage << "\nCommands:\n";
  for (const Subcommand& command : commands) {
    out << "  " << command.name
        << std::string(width + 4 - command.name.size(), ' ') << command.summary
        << "\n";
  }
}

bool AsksForHelp(int argc, char** argv) {
  return argc < 2 || std::strcmp(argv[1], "-h") == 0 ||
         std::strcmp(argv[1], "--help") == 0 ||
         std::strcmp(argv[1], "help") == 0;
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
  if (AsksForHelp(argc, argv)) {
    PrintUsage(usage, commands, std::cout);
    return argc < 2 ? 1 : 0;
  }
  for (const Subcommand& command : commands) {
    if (command.name == argv[1]) {
      CommandLine cli(program + " " + command.name, command.description);
      const std::function<void()> run = command.define(&cli);
      return RunCommand(cli.app(), argc - 1, argv + 1, run);
    }
  }
  std::cerr << "ERROR: unknown command '" << argv[1] << "'\n\n";
  PrintUsage(usage, commands, std::cerr);
  return 1;
}

std::vector<std::string> UnboundFlags(const Subcommand& command) {
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
