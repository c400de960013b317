// uwcolmap: COLMAP-compatible commands of uwmetric. Like `colmap`, the first
// argument names the command and the rest are its flags.
#include "colmap_plugins/exe/align_commands.h"
#include "colmap_plugins/exe/ba_commands.h"
#include "colmap_plugins/exe/command.h"
#include "colmap_plugins/exe/database_commands.h"
#include "colmap_plugins/exe/dense_commands.h"
#include "colmap_plugins/exe/model_commands.h"
#include "colmap_plugins/exe/nav_commands.h"
#include "colmap_plugins/exe/report_commands.h"

int main(int argc, char** argv) {
  return uw::DispatchSubcommand(
      "uwcolmap: uwmetric's COLMAP-compatible commands.\n\n"
      "Usage:\n  uwcolmap <command> [--flag value ...]\n"
      "  uwcolmap <command> --help\n\n"
      "Example:\n  uwcolmap model_analyzer --path sparse/0\n",
      {
          {"bundle_adjuster", uw::RunBundleAdjuster,
           "bundle adjustment fused with navigation, dive offsets, soft rigs"},
          {"database_analyzer", uw::RunDatabaseAnalyzer,
           "print the schema and contents of a COLMAP database"},
          {"dense_mesher", uw::RunDenseMesher,
           "dense surface (PLY) of a model on the CPU: depth maps + Poisson"},
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
          {"survey_report", uw::RunSurveyReport,
           "survey report folder: index.html, figures, CSVs, report.json"},
      },
      argc, argv);
}
