// uwcolmap model_comparer and model_aligner on the default uwsim survey
// reconstructed by stock colmap (fixture uwsim_survey): the figures against
// uwsim's truth (cameras, true surface), and alignment to its navigation.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <fstream>
#include <map>

#include <nlohmann/json.hpp>

#include "colmap_plugins/scene/model_io.h"
#include "common/util/file.h"
#include "common/util/subprocess.h"
#include "tests/support/process.h"
#include "tests/support/uwsim_survey.h"

namespace uw {
namespace {

namespace fs = std::filesystem;
using testing::FreshTestDir;
using testing::Quoted;

const fs::path kSurveyDir = UW_SURVEY_DIR;
const fs::path kSimDir = kSurveyDir / "sim";
const fs::path kSparseDir = kSurveyDir / "sparse" / "0";
const fs::path kUwcolmap = fs::path(UW_BIN_DIR) / "uwcolmap";

nlohmann::json ReadJson(const fs::path& path) {
  return nlohmann::json::parse(ReadFileToString(path));
}

// `flags` name the reference: --truth_dir (with the true surface, whose 1.2
// M triangles take a second to read) or --ref_path.
nlohmann::json Compare(const fs::path& model, const std::string& flags,
                       const fs::path& json) {
  const auto result =
      RunProcess(kUwcolmap.string() + " model_comparer --input_path " +
                     Quoted(model) + " --output_path " + Quoted(json) + flags,
                 true);
  EXPECT_EQ(result.exit_code, 0) << result.output;
  return ReadJson(json);
}

TEST(ModelComparer, MeasuresStockColmapAgainstTheTruth) {
  const fs::path dir = FreshTestDir("uw_model_comparer_test");
  const nlohmann::json compare = Compare(
      kSparseDir, " --truth_dir " + Quoted(kSimDir), dir / "compare.json");

  // The camera RMSE after a similarity, recomputed here with Eigen's
  // Umeyama.
  const Reconstruction truth = ReadModel(kSimDir / "truth");
  const Reconstruction model = ReadModel(kSparseDir);
  std::map<std::string, Eigen::Vector3d> true_centres;
  for (const Image& image : truth.Images()) {
    true_centres[image.name] = image.ProjectionCenter();
  }
  Eigen::Matrix3Xd source(3, model.Images().size());
  Eigen::Matrix3Xd target(3, model.Images().size());
  for (size_t i = 0; i < model.Images().size(); ++i) {
    source.col(i) = model.Images()[i].ProjectionCenter();
    target.col(i) = true_centres.at(model.Images()[i].name);
  }
  const Eigen::Matrix4d world_from_model = Eigen::umeyama(source, target);
  const double rmse =
      std::sqrt((((world_from_model.topLeftCorner<3, 3>() * source).colwise() +
                  world_from_model.topRightCorner<3, 1>()) -
                 target)
                    .colwise()
                    .squaredNorm()
                    .mean());

  const double extent = compare.at("reference_extent_m").get<double>();
  const nlohmann::json& surface = compare.at("surface");
  std::printf(
      "[ figures ] stock colmap vs uwsim truth: %d images, camera RMSE "
      "%.5f m (%.4f %% of %.2f m; Eigen::umeyama %.5f m), rotation RMS %.4f "
      "deg; surface: %d of %d points, signed distance RMS %.5f m, median "
      "%.5f m, median |d| %.5f m, 95 %% |d| %.5f m; dome sagitta %.5f m "
      "(%.4f %%)\n[ figures ] per-segment scale 3D / along track:",
      compare.at("num_common_images").get<int>(),
      compare.at("camera_rmse_m").get<double>(),
      compare.at("camera_rmse_percent_of_extent").get<double>(), extent, rmse,
      compare.at("rotation_rmse_deg").get<double>(),
      surface.at("num_points_used").get<int>(),
      surface.at("num_points").get<int>(), surface.at("rms_m").get<double>(),
      surface.at("median_m").get<double>(),
      surface.at("median_abs_m").get<double>(),
      surface.at("p95_abs_m").get<double>(),
      surface.at("dome").at("sagitta_m").get<double>(),
      surface.at("dome").at("sagitta_percent").get<double>());
  for (const auto& segment : compare.at("segments")) {
    std::printf(" %.5f/%.5f", segment.at("scale_3d").get<double>(),
                segment.at("scale_along_track").get<double>());
  }
  std::printf("\n");

  EXPECT_NEAR(compare.at("camera_rmse_m").get<double>(), rmse, 1e-9);
  EXPECT_LT(rmse, 0.01 * extent);
  ASSERT_EQ(compare.at("segments").size(), 6u);
  for (const auto& segment : compare.at("segments")) {
    EXPECT_NEAR(segment.at("scale_3d").get<double>(), 1.0, 0.01);
  }
  // colmap's points lie on the true surface to millimetres.
  EXPECT_GT(surface.at("num_points_used").get<int>(), 1000);
  EXPECT_LT(surface.at("median_abs_m").get<double>(), 0.005);
  EXPECT_LT(std::abs(surface.at("median_m").get<double>()), 0.005);
  EXPECT_LT(surface.at("p95_abs_m").get<double>(), 0.03);
  EXPECT_TRUE(surface.at("dome").at("valid").get<bool>());
  EXPECT_LT(std::abs(surface.at("dome").at("sagitta_m").get<double>()), 0.01);
  // The reconstruction is in colmap's arbitrary units: the distance ratios
  // give its scale, the inverse of the alignment's.
  EXPECT_NEAR(compare.at("distance_ratios").at("median_ratio").get<double>() *
                  compare.at("alignment")
                      .at("reference_from_model")
                      .at("scale")
                      .get<double>(),
              1.0, 0.01);
}

TEST(ModelComparer, RefusesBadFlagsAndWritesNothing) {
  const fs::path dir = FreshTestDir("uw_model_comparer_test");
  const auto both =
      RunProcess(kUwcolmap.string() + " model_comparer --input_path " +
                     Quoted(kSparseDir) + " --ref_path " + Quoted(kSparseDir) +
                     " --truth_dir " + Quoted(kSimDir) + " --output_path " +
                     Quoted(dir / "compare.json"),
                 true);
  EXPECT_EQ(both.exit_code, 1);
  EXPECT_NE(both.output.find("exactly one of --ref_path and --truth_dir"),
            std::string::npos)
      << both.output;
  const auto missing_mesh = RunProcess(
      kUwcolmap.string() + " model_comparer --input_path " +
          Quoted(kSparseDir) + " --ref_path " + Quoted(kSimDir / "truth") +
          " --mesh_path " + Quoted(dir / "none.ply") + " --output_path " +
          Quoted(dir / "compare.json"),
      true);
  EXPECT_EQ(missing_mesh.exit_code, 1);
  EXPECT_NE(missing_mesh.output.find("none.ply"), std::string::npos)
      << missing_mesh.output;
  EXPECT_FALSE(fs::exists(dir / "compare.json"));
}

ProcessResult Align(const fs::path& output, const std::string& flags) {
  return RunProcess(kUwcolmap.string() + " model_aligner --input_path " +
                        Quoted(kSparseDir) + " --output_path " +
                        Quoted(output) + flags,
                    true);
}

// Aligned to the true navigation, the model lands on the truth (to colmap's
// own error); aligned to uwsim's noisy navigation, it is off by what the
// navigation is off.
TEST(ModelAlignerOnUwsim, NavigationByNameAndByClosestPoint) {
  const fs::path dir = FreshTestDir("uw_model_comparer_test");
  const fs::path true_nav = kSimDir / "truth" / "nav.csv";
  const std::string times =
      " --image_times " + Quoted(kSimDir / "image_times.csv");
  struct Case {
    const char* name;
    std::string flags;
  };
  const std::vector<Case> cases = {
      {"true_nav_by_name", " --nav " + Quoted(true_nav)},
      {"true_nav_closest_point",
       " --nav " + Quoted(true_nav) + times + " --associate closest_point"},
      {"true_nav_closest_point_order",
       " --nav " + Quoted(true_nav) + " --associate closest_point"},
      {"noisy_nav_by_name", " --nav " + Quoted(kSimDir / "nav.csv")},
      {"noisy_nav_unweighted_least_squares",
       " --nav " + Quoted(kSimDir / "nav.csv") + " --robust_alignment 0"},
  };
  std::map<std::string, double> absolute_rmse;
  for (const Case& c : cases) {
    const fs::path output = dir / c.name;
    const auto result =
        Align(output, c.flags + testing::SurveyMountFlags(kSimDir) +
                          " --transform_path " +
                          Quoted(dir / (std::string(c.name) + ".json")));
    ASSERT_EQ(result.exit_code, 0) << c.name << "\n" << result.output;
    const nlohmann::json compare = Compare(
        output, " --alignment none --ref_path " + Quoted(kSimDir / "truth"),
        dir / (std::string(c.name) + "_compare.json"));
    absolute_rmse[c.name] = compare.at("camera_rmse_m").get<double>();
    std::printf(
        "[ figures ] model_aligner %s: camera RMSE vs truth without "
        "re-alignment %.5f m, residual RMS %.5f m\n",
        c.name, absolute_rmse[c.name],
        ReadJson(dir / (std::string(c.name) + ".json"))
            .at("rms_m")
            .get<double>());
  }
  // colmap's own error after a similarity is ~1 mm (previous test).
  EXPECT_LT(absolute_rmse["true_nav_by_name"], 0.005);
  EXPECT_LT(absolute_rmse["true_nav_closest_point"], 0.005);
  EXPECT_LT(absolute_rmse["true_nav_closest_point_order"], 0.005);
  // USBL-like noise of ~1 m per fix and a dive bias over a 6.6 m survey.
  EXPECT_LT(absolute_rmse["noisy_nav_by_name"], 2.0);
  EXPECT_GT(absolute_rmse["noisy_nav_by_name"], 0.05);
}

// The same priors through a database (pose_prior_importer, then
// --database_path) give the same alignment as --nav.
TEST(ModelAlignerOnUwsim, DatabasePriorsMatchNavigation) {
  const fs::path dir = FreshTestDir("uw_model_comparer_test");
  fs::copy_file(kSurveyDir / "database.db", dir / "database.db");
  const fs::path true_nav = kSimDir / "truth" / "nav.csv";
  const auto import =
      RunProcess(kUwcolmap.string() + " pose_prior_importer --database_path " +
                     Quoted(dir / "database.db") + " --nav " +
                     Quoted(true_nav) + testing::SurveyMountFlags(kSimDir),
                 true);
  ASSERT_EQ(import.exit_code, 0) << import.output;
  const auto by_database =
      Align(dir / "db", " --database_path " + Quoted(dir / "database.db") +
                            " --transform_path " + Quoted(dir / "db.json"));
  ASSERT_EQ(by_database.exit_code, 0) << by_database.output;
  const auto by_nav =
      Align(dir / "nav", " --nav " + Quoted(true_nav) +
                             testing::SurveyMountFlags(kSimDir) +
                             " --transform_path " + Quoted(dir / "nav.json"));
  ASSERT_EQ(by_nav.exit_code, 0) << by_nav.output;
  const nlohmann::json db = ReadJson(dir / "db.json");
  const nlohmann::json nav = ReadJson(dir / "nav.json");
  double max_difference = 0.0;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) {
      max_difference = std::max(
          max_difference,
          std::abs(
              db.at("reference_from_model").at("matrix")[r][c].get<double>() -
              nav.at("reference_from_model").at("matrix")[r][c].get<double>()));
    }
  }
  EXPECT_LT(max_difference, 1e-9);
}

// A camera clock 58 days and 3 hours off the navigation's: by name and by
// closest point, one error names the offset that fixes it, and nothing is
// written. (By closest point the times only start the association: the
// closest points used to carry a clock days off to exit 0.)
TEST(ModelAlignerOnUwsim, ACameraClockDaysOffIsRefusedWithItsOffset) {
  const fs::path dir = FreshTestDir("uw_model_comparer_test");
  {
    std::ifstream in(kSimDir / "image_times.csv");
    std::ofstream out(dir / "image_times.csv");
    out.precision(17);
    for (std::string line; std::getline(in, line);) {
      const size_t comma = line.find(',');
      if (line.empty() || line[0] == '#' || line.rfind("image_name", 0) == 0) {
        out << line << "\n";
      } else {
        out << line.substr(0, comma) << ","
            << std::stod(line.substr(comma + 1)) - 5022000.0 << "\n";
      }
    }
  }
  const std::string nav = " --nav " + Quoted(kSimDir / "nav.csv") +
                          " --image_times " + Quoted(dir / "image_times.csv") +
                          testing::SurveyMountFlags(kSimDir);
  for (const std::string associate : {"name", "closest_point"}) {
    const fs::path output = dir / associate;
    const auto result = Align(output, nav + " --associate " + associate);
    EXPECT_EQ(result.exit_code, 1) << associate << "\n" << result.output;
    EXPECT_NE(result.output.find("Is the camera clock off by about 58 d 3 h"),
              std::string::npos)
        << associate << "\n"
        << result.output;
    EXPECT_NE(result.output.find("--time_offset 5022000 puts the median"),
              std::string::npos)
        << result.output;
    EXPECT_FALSE(fs::exists(output));
  }
  // With that offset, the same times align.
  const auto fixed = Align(dir / "fixed", nav + " --time_offset 5022000");
  EXPECT_EQ(fixed.exit_code, 0) << fixed.output;
}

}  // namespace
}  // namespace uw
