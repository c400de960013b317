// scripts/demo.sh, reduced (the fixture demo_reduced, tests/CMakeLists.txt):
// the default survey and laser images of the fixtures instead of generating
// and matching them again, depth maps at 512 px and 2000 Monte Carlo
// samples; every other stage as in the full demo (issue 7, acceptance 2 to
// 4).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <iostream>

#include <nlohmann/json.hpp>

#include "common/util/file.h"
#include "common/util/subprocess.h"
#include "tests/support/process.h"

namespace uw {
namespace {

namespace fs = std::filesystem;
using testing::FreshTestDir;
using testing::Quoted;

const fs::path kDemoDir = UW_DEMO_DIR;
const fs::path kSurveyDir = UW_SURVEY_DIR;
const fs::path kScript = fs::path(UW_SOURCE_DIR) / "scripts" / "demo.sh";

nlohmann::json ReadJson(const fs::path& path) {
  return nlohmann::json::parse(ReadFileToString(path));
}

double ScaleInLog(const fs::path& log) {
  const std::string text = ReadFileToString(log);
  const size_t at = text.find(": scale ");
  if (at == std::string::npos) {
    ADD_FAILURE() << "no scale in " << log;
    return 0.0;
  }
  return std::stod(text.substr(at + 8));
}

TEST(Demo, ReducedDemoRunsEndToEndAndPrintsTheSummary) {
  const std::string output = ReadFileToString(kDemoDir.string() + ".log");
  std::cout << output.substr(
      output.find("=====") == std::string::npos ? 0 : output.find("====="));
  // The summary, every line of it.
  for (const char* line :
       {"Registered images: 33 of 33",
        "Laser scale of the navigation-fused model: s = ",
        "(the truth is inside the interval)",
        "Dense mesh of the navigation-fused model vs the true surface: median ",
        "stock colmap mapper",
        "stock colmap BA + model_aligner (camera centres)",
        "ours: bundle_adjuster --Nav.strategy prior",
        "  + dense_mesher + laserscale apply", "Time per stage (s):",
        "uwcolmap dense_mesher (stock colmap's model and ours)",
        "laserscale apply (both models)", "total (after setup)",
        "Survey report: ", "Laser report: "}) {
    EXPECT_NE(output.find(line), std::string::npos) << line;
  }

  // Acceptance 2: the chain's scale within its own 95 % interval of the
  // truth (the similarity of the navigation-fused model to uwsim's true
  // cameras), and within 1 %.
  const fs::path chain = kDemoDir / "compare" / "chain" / "ours_prior_auto";
  const nlohmann::json scale = ReadJson(chain / "report" / "scale.json");
  const double s = scale.at("scale").get<double>();
  const double low = scale.at("ci95")[0].get<double>();
  const double high = scale.at("ci95")[1].get<double>();
  const nlohmann::json model_compare = ReadJson(chain / "compare.json");
  const double true_scale = model_compare.at("alignment")
                                .at("reference_from_model")
                                .at("scale")
                                .get<double>();
  std::printf(
      "[ figures ] laser scale s = %.5f [%.5f, %.5f], truth %.5f, error "
      "%+.3f %%, %d of %d images\n",
      s, low, high, true_scale, 100.0 * (s / true_scale - 1.0),
      scale.at("num_accepted").get<int>(), scale.at("num_images").get<int>());
  EXPECT_LE(low, true_scale);
  EXPECT_GE(high, true_scale);
  EXPECT_LT(std::abs(s / true_scale - 1.0), 0.01);
  // The Monte Carlo re-sampled the fused model from its covariance (gauge
  // priors) and compared the laser scale with the navigation's.
  EXPECT_EQ(scale.at("model_draws").at("count").get<int>(), 200);
  EXPECT_EQ(scale.at("model_draws").at("gauge"), "priors");
  EXPECT_TRUE(scale.at("variance_by_source").contains("model"));
  EXPECT_TRUE(scale.at("navigation").at("consistent").get<bool>());
  const nlohmann::json report = ReadJson(kDemoDir / "report" / "report.json");
  EXPECT_EQ(report.at("uncertainty").at("gauge"), "priors");
  EXPECT_EQ(report.at("uncertainty").at("num_samples").get<int>(), 200);

  // The dense mesh of the navigation-fused model (acceptance 1's figures).
  const nlohmann::json dense = model_compare.at("dense_surface");
  std::printf(
      "[ figures ] dense mesh of the fused model: median %.5f m = %.4f %% of "
      "%.4f m, coverage %.2f %%\n",
      dense.at("median_distance").get<double>(),
      100.0 * dense.at("median_over_camera_scene_distance").get<double>(),
      dense.at("camera_scene_distance").get<double>(),
      100.0 * dense.at("coverage").get<double>());
  EXPECT_LT(dense.at("median_over_camera_scene_distance").get<double>(), 0.005);
  EXPECT_GE(dense.at("coverage").get<double>(), 0.90);

  // laserscale apply: the model in metres is the truth's size to the
  // scale's own error.
  const fs::path logs = kDemoDir / "compare" / "logs";
  EXPECT_NEAR(ScaleInLog(logs / "compare_ours_prior_auto_laser_similarity.log"),
              true_scale / s, 1e-6);
  EXPECT_TRUE(
      fs::exists(kDemoDir / "compare" / "ours_prior_auto_laser" / "mesh.ply"));

  // Acceptance 4: the same chain for stock colmap's navigation-aligned
  // model; the laser scale corrects its navigation scale error too.
  const std::string chain_csv =
      ReadFileToString(kDemoDir / "compare" / "chain.csv");
  EXPECT_NE(chain_csv.find("\"colmap BA + model_aligner (camera centres)\","),
            std::string::npos)
      << chain_csv;
  const double colmap_before =
      ScaleInLog(logs / "compare_colmap_camera_similarity.log");
  const double colmap_after =
      ScaleInLog(logs / "compare_colmap_camera_laser_similarity.log");
  std::printf(
      "[ figures ] stock colmap + model_aligner: scale error %+.3f %% "
      "before the laser scale, %+.3f %% after\n",
      100.0 * (colmap_before - 1.0), 100.0 * (colmap_after - 1.0));
  EXPECT_LT(std::abs(colmap_after - 1.0), 0.01);
  EXPECT_GT(std::abs(colmap_before - 1.0), std::abs(colmap_after - 1.0));

  // timings.csv: a header, one line per stage, the total.
  const std::string timings = ReadFileToString(kDemoDir / "timings.csv");
  EXPECT_EQ(timings.rfind("stage,seconds\n", 0), 0u) << timings;
  EXPECT_NE(timings.find("\"uwcolmap dense_mesher (stock colmap's model and "
                         "ours)\","),
            std::string::npos)
      << timings;
  EXPECT_NE(timings.find("\"total\","), std::string::npos) << timings;
}

TEST(Demo, RefusesAFolderItDidNotMake) {
  const fs::path dir = FreshTestDir("uw_demo_refuse_test");
  WriteFilesAtomically(
      {{dir / "keep.txt", [](std::ostream& out) { out << "user data\n"; }}},
      false);
  const auto result = RunProcess(
      "UW_BUILD_DIR=" + Quoted(UW_BUILD_DIR) + " bash " + Quoted(kScript) +
          " " + Quoted(dir) + " --no_setup --survey " + Quoted(kSurveyDir),
      true);
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find("was not made by this script"),
            std::string::npos)
      << result.output;
  EXPECT_EQ(ReadFileToString(dir / "keep.txt"), "user data\n");
}

}  // namespace
}  // namespace uw
