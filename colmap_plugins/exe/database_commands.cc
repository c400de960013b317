#include "colmap_plugins/exe/database_commands.h"

#include <iostream>

#include "colmap_plugins/scene/database_stats.h"

namespace uw {
namespace {

void AddDatabaseAnalyzerFlags(CommandLine* cli,
                              DatabaseAnalyzerOptions* options) {
  cli->Add("--database_path", &options->database_path, "COLMAP database")
      ->required();
}

void RunDatabaseAnalyzer(const DatabaseAnalyzerOptions& options) {
  std::cout << FormatDatabaseAnalyzerReport(ComputeDatabaseStats(
      Database::Open(options.database_path, Database::Mode::kReadOnly)));
}

}  // namespace

Subcommand DatabaseAnalyzerCommand() {
  return MakeSubcommand<DatabaseAnalyzerOptions>(
      "database_analyzer", "print the schema and contents of a COLMAP database",
      "Prints the schema of a COLMAP database (3.8 to 4.x, detected from its "
      "tables) and what it holds. Opens the file read-only; never changes "
      "it.\n\n"
      "Example:\n"
      "  uwcolmap database_analyzer --database_path database.db",
      AddDatabaseAnalyzerFlags, RunDatabaseAnalyzer);
}

}  // namespace uw
