#include "colmap_plugins/exe/report_commands.h"

#include <cstdio>
#include <string>

#include "common/cli/command.h"
#include "report/survey_report.h"

namespace uw {

int RunSurveyReport(int argc, char** argv) {
  CLI::App app(
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
      "uwcolmap survey_report");
  SurveyReportInputs inputs;
  SurveyReportOptions options;
  std::string output_path;
  app.add_option("--input_path", inputs.model_path,
                 "COLMAP model the report is about (BIN or TXT); the "
                 "navigation-fused one for a survey map in the navigation's "
                 "frame")
      ->required();
  app.add_option("--output_path", output_path,
                 "Report folder to write (index.html and the rest)")
      ->required();
  app.add_option("--ba_report", inputs.ba_report_path,
                 "bundle_adjuster's ba_report.json: navigation fusion");
  app.add_option("--nav", inputs.nav_path,
                 "nav.csv: navigation track, dives, image count");
  app.add_option("--laser_report", inputs.laser_report_dir,
                 "laserscale estimate's --out folder: scale, overlays");
  app.add_option("--compare_table", inputs.compare_table_path,
                 "scripts/compare_with_colmap.sh's table.csv: stock colmap "
                 "vs ours");
  app.add_option("--dense_comparison", inputs.dense_comparison_path,
                 "model_comparer --dense_mesh_path's compare.json: mesh "
                 "accuracy and coverage");
  app.add_option("--mesh", inputs.mesh_path,
                 "Dense mesh (PLY/OBJ) in the model's frame: survey map, "
                 "mesh figures");
  app.add_option("--timings", inputs.timings_path,
                 "timings.csv (stage,seconds): time per stage");
  app.add_option("--truth_dir", inputs.truth_dir,
                 "uwsim output folder: errors against the truth");
  app.add_option("--title", options.title, "Title of the page")
      ->capture_default_str();
  app.add_option("--map_width", options.map_width_px,
                 "Width of the survey map (px)")
      ->capture_default_str();
  app.add_option("--thumbnail_width", options.thumbnail_width_px,
                 "Width of the spot overlays' thumbnails (px)")
      ->capture_default_str();
  return RunCommand(app, argc, argv, [&] {
    const SurveyReportResult result =
        WriteSurveyReport(inputs, options, output_path);
    for (const std::string& note : result.omitted) {
      std::printf("[survey_report] left out: %s\n", note.c_str());
    }
    std::printf("[survey_report] %zu files, %zu images: %s\n",
                result.files.size(), result.num_images,
                result.index_path.string().c_str());
  });
}

}  // namespace uw
