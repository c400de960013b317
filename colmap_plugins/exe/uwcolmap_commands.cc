#include "colmap_plugins/exe/uwcolmap_commands.h"

#include "colmap_plugins/exe/align_commands.h"
#include "colmap_plugins/exe/ba_commands.h"
#include "colmap_plugins/exe/database_commands.h"
#include "colmap_plugins/exe/dense_commands.h"
#include "colmap_plugins/exe/model_commands.h"
#include "colmap_plugins/exe/nav_commands.h"
#include "colmap_plugins/exe/report_commands.h"

namespace uw {

const std::vector<Subcommand>& UwcolmapCommands() {
  static const std::vector<Subcommand> commands = {
      FromLegacy({"bundle_adjuster", RunBundleAdjuster,
                  "bundle adjustment fused with navigation, dive offsets, soft "
                  "rigs"}),
      FromLegacy({"database_analyzer", RunDatabaseAnalyzer,
                  "print the schema and contents of a COLMAP database"}),
      FromLegacy({"dense_mesher", RunDenseMesher,
                  "dense surface (PLY) of a model on the CPU: depth maps + "
                  "Poisson"}),
      FromLegacy({"lcurve", RunLCurve,
                  "sweep the navigation weight; L-curve plot and corner"}),
      FromLegacy({"model_aligner", RunModelAligner,
                  "align a model to navigation or reference positions "
                  "(similarity)"}),
      ModelAnalyzerCommand(),
      ModelConverterCommand(),
      FromLegacy({"model_comparer", RunModelComparer,
                  "measure a model against another model or uwsim's truth"}),
      PosePriorImporterCommand(),
      FromLegacy({"survey_report", RunSurveyReport,
                  "survey report folder: index.html, figures, CSVs, "
                  "report.json"}),
  };
  return commands;
}

}  // namespace uw
