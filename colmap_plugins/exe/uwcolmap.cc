// uwcolmap: COLMAP-compatible commands of uwmetric. Like `colmap`, the first
// argument names the command and the rest are its flags.
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include "colmap_plugins/exe/align_commands.h"
#include "colmap_plugins/exe/ba_commands.h"
#include "colmap_plugins/exe/database_commands.h"
#include "colmap_plugins/exe/model_commands.h"
#include "colmap_plugins/exe/nav_commands.h"

namespace {

struct Command {
  const char* name;
  int (*run)(int, char**);
  const char* summary;
};

const std::vector<Command>& Commands() {
  static const std::vector<Command> commands = {
      {"bundle_adjuster", uw::RunBundleAdjuster,
       "bundle adjustment fused with navigation, dive offsets, soft rigs"},
      {"database_analyzer", uw::RunDatabaseAnalyzer,
       "print the schema and contents of a COLMAP database"},
      {"lcurve", uw::RunLCurve,
       "sweep the navigation weight; L-curve plot and corner"},
      {"model_aligner", uw::RunModelAligner,
       "align a model to navigation or reference positions (similarity)"},
      {"model_analyzer", uw::RunModelAnalyzer,
       "print statistics of a model (as colmap model_analyzer)"},
      {"model_converter", uw::RunModelConverter,
       "convert a model between BIN and TXT, keeping record order"},
      {"model_comparer", uw::RunModelComparer,
       "measure a model against another model or uwsim's truth"},
      {"pose_prior_importer", uw::RunPosePriorImporter,
       "write camera pose priors from a navigation log into a database"},
  };
  return commands;
}

void PrintUsage(std::ostream& out) {
  out << "uwcolmap: uwmetric's COLMAP-compatible commands.\n\n"
         "Usage:\n  uwcolmap <command> [--flag value ...]\n"
         "  uwcolmap <command> --help\n\n"
         "Example:\n  uwcolmap model_analyzer --path sparse/0\n\n"
         "Commands:\n";
  for (const Command& command : Commands()) {
    out << "  " << command.name
        << std::string(20 - std::strlen(command.name), ' ') << command.summary
        << "\n";
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || std::strcmp(argv[1], "-h") == 0 ||
      std::strcmp(argv[1], "--help") == 0 ||
      std::strcmp(argv[1], "help") == 0) {
    PrintUsage(std::cout);
    return argc < 2 ? 1 : 0;
  }
  for (const Command& command : Commands()) {
    if (command.name == std::string(argv[1])) {
      return command.run(argc - 1, argv + 1);
    }
  }
  std::cerr << "ERROR: unknown command '" << argv[1] << "'\n\n";
  PrintUsage(std::cerr);
  return 1;
}
