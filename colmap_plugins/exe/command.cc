#include "colmap_plugins/exe/command.h"

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

bool ParseColmapBool(const std::string& value, const std::string& flag) {
  if (value == "1" || value == "true") return true;
  if (value == "0" || value == "false") return false;
  throw ErrorAt("--", flag, ": expected 0 or 1, got '", value, "'");
}

}  // namespace uw
