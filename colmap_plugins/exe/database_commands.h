// uwcolmap database_analyzer: what a COLMAP database holds, in which schema.
#pragma once

#include <string>

#include "common/cli/command.h"

namespace uw {

struct DatabaseAnalyzerOptions {
  std::string database_path;
  void Check() const {}
};
Subcommand DatabaseAnalyzerCommand();

}  // namespace uw
