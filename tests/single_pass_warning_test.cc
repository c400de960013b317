// The breakwater's lawnmower plan is one pass: 21 camera centres 6 cm off an
// 11 m line. Positions alone fix a model's rotation about such a line only
// through that scatter (colmap_plugins/ba/track_line.h), and every command
// that places a model by them says so, once, where the user reads it: on
// stderr and in its json.
#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "common/util/file.h"
#include "common/util/subprocess.h"
#include "tests/support/process.h"
#include "tests/support/uwsim_survey.h"

namespace uw {
namespace {

namespace fs = std::filesystem;
using testing::FreshTestDir;
using testing::Quoted;
using testing::SurveyMountFlags;

const fs::path kPlanDir = fs::path(UW_PLANS_DIR) / "breakwater";

size_t Count(const std::string& text, const std::string& what) {
  size_t count = 0;
  for (size_t at = text.find(what); at != std::string::npos;
       at = text.find(what, at + 1)) {
    ++count;
  }
  return count;
}

nlohmann::json ReadJson(const fs::path& path) {
  return nlohmann::json::parse(ReadFileToString(path));
}

// uwsim observe of `plan` into `tracks` with `flags`; its output.
std::string ObserveTracks(const fs::path& plan, const fs::path& tracks,
                          const std::string& flags) {
  const auto observed = RunProcess(
      Quoted(fs::path(UW_BIN_DIR) / "uwsim") + " observe --sim " +
          Quoted(plan) + " --output_path " + Quoted(tracks) + " " + flags,
      true);
  EXPECT_EQ(observed.exit_code, 0) << observed.output;
  return observed.output;
}

class SinglePass : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = FreshTestDir(
        "uw_single_pass_" +
        std::string(
            ::testing::UnitTest::GetInstance()->current_test_info()->name()));
    // Tracks in a frame of their own (scale 0.3-3), as a mapper leaves them.
    ObserveTracks(kPlanDir, dir_ / "tracks",
                  "--num_points 2500 --init perturbed --seed 3");
  }

  std::string Uwcolmap(const std::string& command,
                       const std::string& flags) const {
    return Quoted(fs::path(UW_BIN_DIR) / "uwcolmap") + " " + command +
           " --input_path " + Quoted(dir_ / "tracks") + " --nav " +
           Quoted(kPlanDir / "nav.csv") + SurveyMountFlags(kPlanDir) + flags;
  }

  fs::path dir_;
};

TEST_F(SinglePass, TheAdjusterWarnsOnceAndTheAttitudeSilencesIt) {
  const auto adjusted = RunProcess(
      Uwcolmap("bundle_adjuster",
               " --output_path " + Quoted(dir_ / "ba") + " --BA.covariance 1"),
      true);
  ASSERT_EQ(adjusted.exit_code, 0) << adjusted.output;
  // Once, though the adjuster and the covariance both carry it.
  EXPECT_EQ(Count(adjusted.output,
                  "WARNING: navigation positions on one pass: "
                  "the 21 camera centres lie nearly on one "
                  "line"),
            1u)
      << adjusted.output;
  for (const fs::path& json :
       {dir_ / "ba" / "ba_report.json",
        dir_ / "ba" / "covariance" / "covariance.json"}) {
    const auto warnings =
        ReadJson(json).at("warnings").get<std::vector<std::string>>();
    EXPECT_EQ(std::count_if(warnings.begin(), warnings.end(),
                            [](const std::string& warning) {
                              return warning.find("nearly on one line") !=
                                     std::string::npos;
                            }),
              1)
        << json;
  }

  const auto with_attitude =
      RunProcess(Uwcolmap("bundle_adjuster", " --output_path " +
                                                 Quoted(dir_ / "ba_attitude") +
                                                 " --Nav.use_attitude 1"),
                 true);
  ASSERT_EQ(with_attitude.exit_code, 0) << with_attitude.output;
  EXPECT_EQ(Count(with_attitude.output, "nearly on one line"), 0u)
      << with_attitude.output;
}

TEST_F(SinglePass, TheAlignerWarns) {
  const auto aligned = RunProcess(
      Uwcolmap("model_aligner", " --output_path " + Quoted(dir_ / "aligned") +
                                    " --transform_path " +
                                    Quoted(dir_ / "sim3.json")),
      true);
  ASSERT_EQ(aligned.exit_code, 0) << aligned.output;
  EXPECT_EQ(Count(aligned.output,
                  "WARNING: the aligned 21 camera centres lie "
                  "nearly on one line"),
            1u)
      << aligned.output;
  EXPECT_EQ(ReadJson(dir_ / "sim3.json").at("warnings").size(), 1u);
}

// The README's comparison: each step's warnings on stderr with its name,
// and --Nav.use_attitude 1 for the fused rows, which then need no warning,
// while the rows placed by positions alone keep theirs.
TEST_F(SinglePass, CompareWithColmapRepeatsTheWarningsAndTakesTheAttitude) {
  const auto compared = RunProcess(
      "UWCOLMAP=" + Quoted(fs::path(UW_BIN_DIR) / "uwcolmap") + " bash " +
          Quoted(fs::path(UW_SOURCE_DIR) / "scripts" /
                 "compare_with_colmap.sh") +
          " " + Quoted(kPlanDir) + " " + Quoted(dir_ / "tracks") + " " +
          Quoted(dir_ / "compare") + SurveyMountFlags(kPlanDir) +
          " --Nav.use_attitude 1",
      true);
  ASSERT_EQ(compared.exit_code, 0) << compared.output;
  for (const char* step :
       {"ours_model_aligner: WARNING: the aligned 21 camera centres",
        "ours_posterior: WARNING: navigation positions on one pass"}) {
    EXPECT_NE(compared.output.find(step), std::string::npos) << step << "\n"
                                                             << compared.output;
  }
  EXPECT_EQ(
      compared.output.find("ours_prior_auto: WARNING: navigation positions"),
      std::string::npos)
      << compared.output;
  EXPECT_NE(ReadFileToString(dir_ / "compare" / "table.txt")
                .find("(--Nav.use_attitude 1)"),
            std::string::npos);
}

// The scarp's two stacked lines with 120 tracked points per image (as the
// NEES runs observe them): the last images of a line share only two-view
// points, so the images leave their distances free (scale_transfer.h), and
// the adjuster names them.
TEST(SinglePassScarp, TheAdjusterNamesImagesWithoutScaleTransfer) {
  const fs::path plan = fs::path(UW_PLANS_DIR) / "scarp";
  const fs::path dir = FreshTestDir("uw_single_pass_scarp");
  ObserveTracks(plan, dir / "tracks", "--num_points 32160 --seed 1001");
  // The warning needs no converged adjustment: 10 iterations.
  const auto adjusted = RunProcess(
      Quoted(fs::path(UW_BIN_DIR) / "uwcolmap") +
          " bundle_adjuster --input_path " + Quoted(dir / "tracks") +
          " --output_path " + Quoted(dir / "ba") + " --nav " +
          Quoted(plan / "nav.csv") + SurveyMountFlags(plan) +
          " --Nav.use_attitude 1 --BundleAdjustment.max_num_iterations 10"
          " --BundleAdjustment.unconverged warn",
      true);
  ASSERT_EQ(adjusted.exit_code, 0) << adjusted.output;
  EXPECT_NE(adjusted.output.find("images share no point that 3 images see"),
            std::string::npos)
      << adjusted.output;
  EXPECT_NE(adjusted.output.find("00132.png"), std::string::npos);
}

// The same plan as a mapper would leave it (uwsim observe drops the line
// ends, --min_registration_points 30) and without navigation: colmap's
// monotonic Levenberg-Marquardt crawls along the two lines' weak bending
// and stops at its limit; the non-monotonic steps the adjuster takes by
// default reach a lower cost, converged, in far fewer (docs/uwcolmap.md).
TEST(SinglePassScarp, NonMonotonicStepsConvergeWhereColmapsCrawl) {
  const fs::path plan = fs::path(UW_PLANS_DIR) / "scarp";
  const fs::path dir = FreshTestDir("uw_single_pass_scarp_steps");
  const std::string observed = ObserveTracks(
      plan, dir / "tracks",
      "--num_points 32160 --seed 1000 --min_registration_points 30");
  EXPECT_NE(observed.find("images dropped"), std::string::npos) << observed;
  EXPECT_NE(observed.find("00133.png"), std::string::npos);
  const auto adjust = [&](const std::string& name, const std::string& flags) {
    const auto adjusted = RunProcess(
        Quoted(fs::path(UW_BIN_DIR) / "uwcolmap") +
            " bundle_adjuster --input_path " + Quoted(dir / "tracks") +
            " --output_path " + Quoted(dir / name) + flags,
        true);
    EXPECT_EQ(adjusted.exit_code, 0) << adjusted.output;
    EXPECT_EQ(adjusted.output.find("images share no point that 3 images see"),
              std::string::npos)
        << adjusted.output;
    return ReadJson(dir / name / "ba_report.json");
  };
  const nlohmann::json ours = adjust("ours", "");
  const nlohmann::json colmaps =
      adjust("colmaps",
             " --BundleAdjustment.use_nonmonotonic_steps 0"
             " --BundleAdjustment.function_tolerance 0"
             " --BundleAdjustment.max_num_iterations 40"
             " --BundleAdjustment.unconverged warn");
  EXPECT_EQ(ours.at("termination"), "CONVERGENCE");
  EXPECT_LE(ours.at("iterations").get<int>(), 40);
  EXPECT_TRUE(ours.at("warnings").empty()) << ours.at("warnings");
  EXPECT_EQ(colmaps.at("termination"), "NO_CONVERGENCE");
  EXPECT_EQ(colmaps.at("warnings").size(), 1u);
  const auto cost = [](const nlohmann::json& report) {
    return report.at("final_cost")
        .at("reprojection")
        .at("weighted_cost")
        .get<double>();
  };
  EXPECT_LT(cost(ours), cost(colmaps));
}

}  // namespace
}  // namespace uw
