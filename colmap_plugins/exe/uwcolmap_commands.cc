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
      BundleAdjusterCommand(),   CovarianceEstimatorCommand(),
      DatabaseAnalyzerCommand(), DenseMesherCommand(),
      LCurveCommand(),           ModelAlignerCommand(),
      ModelAnalyzerCommand(),    ModelConverterCommand(),
      ModelComparerCommand(),    PosePriorImporterCommand(),
      ImageTimesCommand(),       SurveyReportCommand(),
  };
  return commands;
}

}  // namespace uw
