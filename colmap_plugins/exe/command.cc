#include "colmap_plugins/exe/command.h"

#include <algorithm>
#include <cstring>
#include <iostream>

#include "colmap_plugins/util/error.h"

namespace uw {

int RunCommand(CLI::App& app, int argc, char** argv,
               const std::function<void()>& body) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    return app.exit(error) == 0 ? 0 : 2;
  }
  try {
    body();
  } catch (const std::exception& error) {
    std::cerr << "ERROR: " << error.what() << std::endl;
    return 1;
  }
  return 0;
}

int DispatchSubcommand(const std::string& usage,
                       const std::vector<Subcommand>& commands, int argc,
                       char** argv) {
  const auto print_usage = [&](std::ostream& out) {
    size_t width = 0;
    for (const Subcommand& command : commands) {
      width = std::max(width, std::strlen(command.name));
    }
    out << usage << "\nCommands:\n";
    for (const Subcommand& command : commands) {
      out << "  " << command.name
          << std::string(width + 4 - std::strlen(command.name), ' ')
          << command.summary << "\n";
    }
  };
  if (argc < 2 || std::strcmp(argv[1], "-h") == 0 ||
      std::strcmp(argv[1], "--help") == 0 ||
      std::strcmp(argv[1], "help") == 0) {
    print_usage(std::cout);
    return argc < 2 ? 1 : 0;
  }
  for (const Subcommand& command : commands) {
    if (command.name == std::string(argv[1])) {
      return command.run(argc - 1, argv + 1);
    }
  }
  std::cerr << "ERROR: unknown command '" << argv[1] << "'\n\n";
  print_usage(std::cerr);
  return 1;
}

bool ParseColmapBool(const std::string& value, const std::string& flag) {
  if (value == "1" || value == "true") return true;
  if (value == "0" || value == "false") return false;
  throw ErrorAt("--", flag, ": expected 0 or 1, got '", value, "'");
}

}  // namespace uw
