#include "colmap_plugins/exe/report_commands.h"

#include <fmt/format.h>

namespace uw {
namespace {

void AddSurveyReportFlags(CommandLine* cli,
                          SurveyReportCommandOptions* options) {
  SurveyReportInputs& inputs = options->inputs;
  cli->Add("--input_path", &inputs.model_path,
           "COLMAP model the report is about (BIN or TXT); the "
           "navigation-fused one for a survey map in the navigation's frame")
      ->required();
  cli->Add("--output_path", &options->output_path,
           "Report folder to write (index.html and the rest)")
      ->required();
  cli->Add("--ba_report", &inputs.ba_report_path,
           "bundle_adjuster's ba_report.json: navigation fusion");
  cli->Add("--nav", &inputs.nav_path,
           "nav.csv: navigation track, dives, image count");
  cli->Add("--laser_report", &inputs.laser_report_dir,
           "laserscale estimate's --out folder: scale, overlays");
  cli->Add("--compare_table", &inputs.compare_table_path,
           "scripts/compare_with_colmap.sh's table.csv: stock colmap vs ours");
  cli->Add("--dense_comparison", &inputs.dense_comparison_path,
           "model_comparer --dense_mesh_path's compare.json: mesh accuracy "
           "and coverage");
  cli->Add("--mesh", &inputs.mesh_path,
           "Dense mesh (PLY, OBJ, STL, glTF, ...) in the model's frame: survey "
           "map, mesh "
           "figures");
  cli->Add("--timings", &inputs.timings_path,
           "timings.csv (stage,seconds): time per stage");
  cli->Add("--truth_dir", &inputs.truth_dir,
           "uwsim output folder: errors against the truth");
  cli->Add("--covariance", &inputs.covariance_dir,
           "covariance_estimator's output folder (or bundle_adjuster "
           "--BA.covariance 1's OUTPUT/covariance): the model's uncertainty");
  SurveyReportOptions& report = options->report;
  cli->Add("--title", &report.title, "Title of the page");
  cli->Add("--map_width", &report.map_width_px, "Width of the survey map (px)");
  cli->Add("--thumbnail_width", &report.thumbnail_width_px,
           "Width of the spot overlays' thumbnails (px)");
}

void RunSurveyReport(const SurveyReportCommandOptions& options) {
  const SurveyReportResult result =
      WriteSurveyReport(options.inputs, options.report, options.output_path);
  for (const std::string& note : result.omitted) {
    fmt::print("[survey_report] left out: {}\n", note);
  }
  fmt::print("[survey_report] {} files, {} images: {}\n", result.files.size(),
             result.num_images, result.index_path.string());
}

}  // namespace

Subcommand SurveyReportCommand() {
  return MakeSubcommand<SurveyReportCommandOptions>(
      "survey_report",
      "survey report folder: index.html, figures, CSVs, report.json",
      "A survey report for a cruise report: one self-contained folder "
      "(index.html, report.json, CSVs, PNGs; relative links, no network) "
      "with a summary, a survey map (dense mesh from above, navigation, "
      "cameras), the laser scale with its 95 % interval per laser / pair "
      "and per segment, the spot overlays, the navigation fusion (prior "
      "residuals, lambda, dive offsets), stock colmap against uwmetric, the "
      "dense surface's accuracy and coverage, the time per stage, and how "
      "to read it all. Every input but the model is optional: a section "
      "without its input is left out with a note. See "
      "docs/uwcolmap.md#survey_report.\n\n"
      "Example (scripts/demo.sh's output folder OUT):\n"
      "  uwcolmap survey_report --input_path OUT/compare/ours_prior_auto "
      "--ba_report OUT/compare/ours_prior_auto/ba_report.json --nav "
      "OUT/sim/nav.csv --laser_report OUT/laser/report --compare_table "
      "OUT/compare/table.csv --dense_comparison OUT/dense/compare.json "
      "--mesh OUT/dense/mesh.ply --timings OUT/timings.csv --truth_dir "
      "OUT/sim --output_path OUT/report",
      AddSurveyReportFlags, RunSurveyReport);
}

}  // namespace uw
