#include "colmap_plugins/ba/nav_bundle_adjustment_controller.h"

#include <algorithm>
#include <cmath>
#include <fstream>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "colmap_plugins/ba/nav_inputs.h"
#include "colmap_plugins/ba/test_scene.h"
#include "common/util/error.h"
#include "common/util/error_testing.h"
#include "tests/support/process.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

// The test scene's model in a frame of its own (as SfM leaves it), so that
// the controller's initial alignment has something to do.
Reconstruction ModelInItsOwnFrame(const test::TestScene& scene) {
  Reconstruction model = scene.observed;
  Sim3d model_from_world;
  model_from_world.scale = 0.4;
  model_from_world.rotation =
      Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()));
  model_from_world.translation = Eigen::Vector3d(3.0, -1.0, 0.5);
  TransformReconstruction(model_from_world, &model);
  return model;
}

// Small enough for a second per adjustment.
test::TestScene SmallScene() {
  test::TestSceneOptions options;
  options.num_lines = 2;
  options.images_per_line = 8;
  options.num_points = 600;
  return test::MakeTestScene(options);
}

NavBundleAdjustmentControllerOptions FixedWeight(double weight_px_per_m) {
  NavBundleAdjustmentControllerOptions options;
  options.input_path = "scene";
  options.adjuster = test::FixedIntrinsics();
  options.weight.selection = NavWeightSelection::kFixed;
  options.weight.fixed_px_per_m = weight_px_per_m;
  return options;
}

NavInputs InputsOf(const test::TestScene& scene) {
  NavInputs inputs;
  inputs.priors = scene.priors;
  return inputs;
}

// nav.csv of the scene's priors (a down-looking camera at the vehicle's
// reference point, `position_sigma` per axis), plus `extra_rows`.
fs::path WriteNav(const test::TestScene& scene, const fs::path& dir,
                  const std::string& extra_rows = "",
                  double position_sigma = 0.3) {
  const fs::path path = dir / "nav.csv";
  std::ofstream out(path);
  out << "image_name,time,dive,x,y,z,roll,pitch,yaw,std_x,std_y,std_z,"
         "std_roll,std_pitch,std_yaw\n";
  for (const ImagePosePrior& prior : scene.priors) {
    const Eigen::Vector3d& p = prior.position_in_world;
    out << fmt::format(
        "{},{},1,{:.17g},{:.17g},{:.17g},0,0,0,{:g},{:g},{:g},1,1,1\n",
        scene.observed.FindImage(prior.image_id)->name, prior.image_id, p.x(),
        p.y(), p.z(), position_sigma, position_sigma, position_sigma);
  }
  out << extra_rows;
  return path;
}

// The progress lines of a run, in order.
ProgressLines Into(std::vector<std::string>* lines) {
  return [lines](const std::string& line) { lines->push_back(line); };
}

TEST(NavBundleAdjustmentController, CheckHoldsTheRulesBetweenOptions) {
  NavBundleAdjustmentControllerOptions options;
  EXPECT_NO_THROW(options.Check());
  options.adjuster.use_attitude = true;
  ExpectErrorContaining([&] { options.Check(); },
                        "--Nav.use_attitude and --Dive.offsets need --nav");
  options.priors.nav.nav_path = "nav.csv";
  EXPECT_NO_THROW(options.Check());

  options = {};
  options.priors.database_path = "database.db";
  options.adjuster.dive_offsets = true;
  ExpectErrorContaining([&] { options.Check(); }, "need --nav");

  options = {};
  options.priors.override_sigma = true;
  ExpectErrorContaining(
      [&] { options.Check(); },
      "--Nav.override_sigma 1 needs --Nav.position_sigma > 0");
  options.priors.position_sigma_m = 0.5;
  EXPECT_NO_THROW(options.Check());

  options = {};
  options.adjuster.function_tolerance = -1.0;
  ExpectErrorContaining([&] { options.Check(); }, "tolerances must be >= 0");

  NavLCurveOptions lcurve;
  EXPECT_NO_THROW(lcurve.Check());
  lcurve.adjuster.dive_offsets = true;
  ExpectErrorContaining([&] { lcurve.Check(); }, "need --nav");
}

TEST(NavBundleAdjustmentController, StrategyAndWeightAsTheFlagsSpellThem) {
  for (const NavStrategy strategy :
       {NavStrategy::kPrior, NavStrategy::kPosterior}) {
    EXPECT_EQ(NavStrategyFromName(NavStrategyName(strategy)), strategy);
  }
  ExpectErrorContaining([] { NavStrategyFromName("both"); },
                        "--Nav.strategy both: prior or posterior");

  EXPECT_EQ(NavWeightFromText("auto").selection,
            NavWeightSelection::kNoiseLevels);
  EXPECT_EQ(NavWeightFromText("corner").selection,
            NavWeightSelection::kLCurveCorner);
  EXPECT_EQ(NavWeightFromText("balance").selection,
            NavWeightSelection::kLCurveBalance);
  const NavWeight fixed = NavWeightFromText("2.5");
  EXPECT_EQ(fixed.selection, NavWeightSelection::kFixed);
  EXPECT_EQ(fixed.fixed_px_per_m, 2.5);
  for (const char* text : {"auto", "corner", "balance", "2.5"}) {
    EXPECT_EQ(NavWeightText(NavWeightFromText(text)), text);
  }
  ExpectErrorContaining([] { NavWeightFromText("heavy"); },
                        "--Nav.weight heavy: a number (px/m), auto, corner or "
                        "balance");
}

// The prior strategy: the model is moved onto the priors, then adjusted
// with the navigation at the given weight.
TEST(NavBundleAdjustmentController, PriorStrategyAlignsThenFusesAtTheWeight) {
  const test::TestScene scene = SmallScene();
  Reconstruction model = ModelInItsOwnFrame(scene);
  std::vector<std::string> lines;
  const NavBundleAdjustmentResult result = AdjustModelWithNavigation(
      FixedWeight(2.0), InputsOf(scene), &model, Into(&lines));
  EXPECT_TRUE(lines.empty()) << lines.front();
  EXPECT_EQ(result.num_priors, scene.priors.size());
  EXPECT_EQ(result.report.weight_px_per_m, 2.0);
  EXPECT_EQ(result.report.prior_residuals.size(), scene.priors.size());
  EXPECT_FALSE(result.noise_levels);
  EXPECT_FALSE(result.lcurve);
  EXPECT_FALSE(result.world_from_adjusted_model);
  // Metres again, within the navigation's noise (0.3 m per axis).
  EXPECT_LT(test::CameraCenterRmse(model, scene.truth), 0.25);
  EXPECT_GT(result.total_time_s, 0.0);

  const std::string summary =
      FormatNavBundleAdjustmentSummary(FixedWeight(2.0), result, model);
  EXPECT_EQ(summary.rfind("term                  blocks    initial MS      "
                          "final MS\n",
                          0),
            0u)
      << summary;
  EXPECT_NE(summary.find("Dive 1: 16 priors, camera minus prior: mean ["),
            std::string::npos)
      << summary;
  EXPECT_NE(summary.find(" iterations, "), std::string::npos) << summary;

  const nlohmann::json json =
      NavBundleAdjustmentJson(FixedWeight(2.0), result, model);
  EXPECT_EQ(json["run"]["strategy"], "prior");
  EXPECT_EQ(json["run"]["camera_on_vehicle"],
            "mount down, lever arm 0,0,0 m, boresight 0,0,0 deg, time offset "
            "0 s");
  EXPECT_EQ(json["total_time_s"], result.total_time_s);
  EXPECT_FALSE(json.contains("lcurve"));
}

TEST(NavBundleAdjustmentController, AutoWeightIsTheNoiseLevelsLambda) {
  const test::TestScene scene = SmallScene();
  Reconstruction model = ModelInItsOwnFrame(scene);
  NavBundleAdjustmentControllerOptions options = FixedWeight(0.0);
  options.weight = NavWeightFromText("auto");
  std::vector<std::string> lines;
  const NavBundleAdjustmentResult result =
      AdjustModelWithNavigation(options, InputsOf(scene), &model, Into(&lines));
  ASSERT_TRUE(result.noise_levels);
  EXPECT_EQ(result.report.weight_px_per_m,
            result.noise_levels->weight_px_per_m);
  // 0.5 px against 0.3 m.
  EXPECT_NEAR(result.report.weight_px_per_m, 0.5 / 0.3, 0.5);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0],
            "Noise levels: images-only adjustment, then its similarity to "
            "the navigation");
  EXPECT_EQ(lines[1].rfind("  sigma_v = ", 0), 0u) << lines[1];
  EXPECT_NE(lines[1].find(fmt::format("lambda = {:g} px/m",
                                      result.report.weight_px_per_m)),
            std::string::npos)
      << lines[1];
  const nlohmann::json json = NavBundleAdjustmentJson(options, result, model);
  EXPECT_EQ(json["run"]["noise_levels"]["weight_px_per_m"],
            result.noise_levels->weight_px_per_m);
}

// The L-curve's balance point, from a sweep around the noise-level lambda.
TEST(NavBundleAdjustmentController, BalanceWeightComesFromTheSweep) {
  const test::TestScene scene = SmallScene();
  Reconstruction model = ModelInItsOwnFrame(scene);
  NavBundleAdjustmentControllerOptions options = FixedWeight(0.0);
  options.weight = NavWeightFromText("balance");
  options.lcurve_steps = 7;
  std::vector<std::string> lines;
  const NavBundleAdjustmentResult result =
      AdjustModelWithNavigation(options, InputsOf(scene), &model, Into(&lines));
  ASSERT_TRUE(result.lcurve);
  ASSERT_TRUE(result.lcurve->balance_weight_px_per_m);
  EXPECT_EQ(result.lcurve->points.size(), 7u);
  EXPECT_EQ(result.report.weight_px_per_m,
            *result.lcurve->balance_weight_px_per_m);
  // Noise levels (2), the sweep's range, 7 adjustments, the choice.
  ASSERT_EQ(lines.size(), 2u + 1u + 7u + 1u);
  EXPECT_EQ(lines[2].rfind("L-curve: 7 adjustments, lambda from ", 0), 0u);
  EXPECT_EQ(lines[3].rfind("  [1/7] lambda ", 0), 0u) << lines[3];
  EXPECT_EQ(lines.back(), fmt::format("L-curve: lambda = {:g} px/m (balance)",
                                      result.report.weight_px_per_m));
  EXPECT_TRUE(
      NavBundleAdjustmentJson(options, result, model).contains("lcurve"));
}

// The posterior strategy: what colmap bundle_adjuster + model_aligner do.
TEST(NavBundleAdjustmentController, PosteriorStrategyAlignsAfterAPlainBa) {
  const test::TestScene scene = SmallScene();
  Reconstruction model = ModelInItsOwnFrame(scene);
  NavBundleAdjustmentControllerOptions options = FixedWeight(2.0);
  options.strategy = NavStrategy::kPosterior;
  const NavBundleAdjustmentResult result =
      AdjustModelWithNavigation(options, InputsOf(scene), &model);
  EXPECT_TRUE(result.report.prior_residuals.empty());
  ASSERT_TRUE(result.world_from_adjusted_model);
  EXPECT_NEAR(result.world_from_adjusted_model->scale, 1.0 / 0.4, 0.1);
  EXPECT_LT(test::CameraCenterRmse(model, scene.truth), 0.25);
  const nlohmann::json json = NavBundleAdjustmentJson(options, result, model);
  EXPECT_EQ(json["run"]["strategy"], "posterior");
  EXPECT_TRUE(json["run"].contains("posterior_similarity"));
}

// Priors in degrees of longitude and latitude, read as metres, their
// sigmas too (3e-6 deg): the model would be adjusted at a scale of 1e-5
// and handed back with exit 0.
TEST(NavBundleAdjustmentController, RefusesAnImplausibleAlignment) {
  const test::TestScene scene = SmallScene();
  NavInputs degrees = InputsOf(scene);
  for (ImagePosePrior& prior : degrees.priors) {
    Eigen::Vector3d& p = prior.position_in_world;
    p = Eigen::Vector3d(5.4 + p.x() / (111320.0 * std::cos(43.1 * M_PI / 180)),
                        43.1 + p.y() / 111320.0, p.z() / 111320.0);
    prior.position_covariance = 9e-12 * Eigen::Matrix3d::Identity();
  }
  for (const NavStrategy strategy :
       {NavStrategy::kPrior, NavStrategy::kPosterior}) {
    NavBundleAdjustmentControllerOptions options = FixedWeight(2.0);
    options.strategy = strategy;
    Reconstruction model = ModelInItsOwnFrame(scene);
    ExpectErrorContaining(
        [&] { AdjustModelWithNavigation(options, degrees, &model); },
        "Are the positions latitude/longitude in degrees, or another unit, "
        "read as metres?\n(--Nav.accept_implausible 1 goes on regardless)");
    options.priors.plausibility.accept_implausible = true;
    model = ModelInItsOwnFrame(scene);
    const NavBundleAdjustmentResult result =
        AdjustModelWithNavigation(options, degrees, &model);
    const std::vector<std::string>& warnings = result.report.warnings;
    EXPECT_TRUE(std::any_of(warnings.begin(), warnings.end(), [](auto& w) {
      return w.find("(accepted: --Nav.accept_implausible 1)") !=
             std::string::npos;
    })) << NavStrategyName(strategy);
  }
  // The L-curve aligns first, too.
  NavLCurveOptions lcurve;
  lcurve.input_path = "scene";
  lcurve.adjuster = test::FixedIntrinsics();
  const fs::path dir = testing::FreshTestDir("uw_controller_implausible");
  // nav.csv in degrees: the scene's priors converted as above.
  test::TestScene in_degrees = scene;
  in_degrees.priors = degrees.priors;
  lcurve.priors.nav.nav_path = WriteNav(in_degrees, dir, "", 3e-6);
  ExpectErrorContaining(
      [&] { SweepModelLCurve(lcurve, ModelInItsOwnFrame(scene)); },
      "latitude/longitude in degrees");
  // Accepted, the warnings say what the log alone looks like, too.
  NavBundleAdjustmentControllerOptions from_log = FixedWeight(2.0);
  from_log.priors = lcurve.priors;
  from_log.priors.plausibility.accept_implausible = true;
  Reconstruction model = ModelInItsOwnFrame(scene);
  const std::vector<std::string> warnings =
      AdjustModelWithNavigation(from_log, &model).report.warnings;
  for (const std::string text : {"longitude and latitude in degrees?",
                                 "(accepted: --Nav.accept_implausible 1)"}) {
    EXPECT_EQ(std::count_if(warnings.begin(), warnings.end(),
                            [&](const std::string& warning) {
                              return warning.find(text) != std::string::npos;
                            }),
              1)
        << text;
  }
}

// A USBL export: time and position, no attitude, no sigmas. It is fused with
// --Nav.position_sigma; --Nav.use_attitude 1 has nothing to use.
TEST(NavBundleAdjustmentController, APositionOnlyLogIsFusedWithoutAttitude) {
  const test::TestScene scene = SmallScene();
  const fs::path dir = testing::FreshTestDir("uw_controller_position_only");
  const fs::path nav = dir / "usbl.csv";
  {
    std::ofstream out(nav);
    out << "image_name,time,x,y,z\n";
    for (const ImagePosePrior& prior : scene.priors) {
      const Eigen::Vector3d& p = prior.position_in_world;
      out << fmt::format("{},{},{:.17g},{:.17g},{:.17g}\n",
                         scene.observed.FindImage(prior.image_id)->name,
                         prior.image_id, p.x(), p.y(), p.z());
    }
  }
  NavBundleAdjustmentControllerOptions options = FixedWeight(2.0);
  options.priors.nav.nav_path = nav;
  Reconstruction model = ModelInItsOwnFrame(scene);
  ExpectErrorContaining(
      [&] { AdjustModelWithNavigation(options, &model); },
      "has no positive-definite position covariance (a zero sigma in the "
      "log?); give --Nav.position_sigma");
  options.priors.position_sigma_m = 0.3;
  options.adjuster.use_attitude = true;
  ExpectErrorContaining(
      [&] { AdjustModelWithNavigation(options, &model); },
      "--Nav.use_attitude 1: " + nav.string() +
          " gives no camera rotations (a log needs roll, pitch and yaw or "
          "heading columns, with their sigmas)");
  options.adjuster.use_attitude = false;
  const NavBundleAdjustmentResult result =
      AdjustModelWithNavigation(options, &model);
  ASSERT_TRUE(result.world_frame);
  EXPECT_EQ(WorldFrameText(*result.world_frame), "the log's x,y,z (m)");
  EXPECT_EQ(
      NavBundleAdjustmentJson(options, result, model)["run"]["world_frame"],
      "the log's x,y,z (m)");
  EXPECT_EQ(result.num_priors, scene.priors.size());
  EXPECT_LT(test::CameraCenterRmse(model, scene.truth), 0.25);
}

// A prior from a log without position sigmas still carries its lever arm's
// circle: --Nav.position_sigma adds the vehicle's share to it, and replaces
// it only with --Nav.override_sigma 1.
TEST(NavBundleAdjustmentController, GivenSigmasAddToTheLeverArmsShare) {
  const test::TestScene scene = SmallScene();
  CameraPrior prior;
  prior.image_name = scene.observed.Images().front().name;
  prior.position_covariance = Eigen::Vector3d(0.2, 0.2, 0.0).asDiagonal();
  const NavInputs added =
      NavInputsForModel({prior}, nullptr, scene.observed, 0.3, false);
  ASSERT_EQ(added.priors.size(), 1u);
  EXPECT_LT((added.priors[0].position_covariance -
             Eigen::Matrix3d(Eigen::Vector3d(0.29, 0.29, 0.09).asDiagonal()))
                .norm(),
            1e-15);
  const NavInputs replaced =
      NavInputsForModel({prior}, nullptr, scene.observed, 0.3, true);
  EXPECT_LT((replaced.priors[0].position_covariance -
             0.09 * Eigen::Matrix3d::Identity())
                .norm(),
            1e-15);
}

// A single pass with position priors only: its rotation about the pass is
// not what the positions can hold (track_line.h), which the report says;
// on two lines it says nothing.
TEST(NavBundleAdjustmentController, WarnsWhenPositionsLieOnOneLine) {
  test::TestSceneOptions scene_options;
  scene_options.num_lines = 1;
  scene_options.images_per_line = 10;
  scene_options.wiggle_m = 0.05;
  scene_options.num_points = 600;
  const test::TestScene pass = test::MakeTestScene(scene_options);
  Reconstruction model = ModelInItsOwnFrame(pass);
  const NavBundleAdjustmentControllerOptions options = FixedWeight(2.0);
  const NavBundleAdjustmentResult result =
      AdjustModelWithNavigation(options, InputsOf(pass), &model);
  const nlohmann::json json = NavBundleAdjustmentJson(options, result, model);
  ASSERT_EQ(json["warnings"].size(), 1u);
  EXPECT_NE(json["warnings"][0].get<std::string>().find("nearly on one line"),
            std::string::npos);
  Reconstruction lawnmower = ModelInItsOwnFrame(SmallScene());
  const NavBundleAdjustmentResult lines =
      AdjustModelWithNavigation(options, InputsOf(SmallScene()), &lawnmower);
  EXPECT_TRUE(lines.report.warnings.empty());
}

TEST(NavBundleAdjustmentController, WithoutPriorsItIsAPlainAdjustment) {
  const test::TestScene scene = SmallScene();
  Reconstruction model = scene.observed;
  std::vector<std::string> lines;
  const NavBundleAdjustmentResult result =
      AdjustModelWithNavigation(FixedWeight(2.0), &model, Into(&lines));
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0], fmt::format("Model: scene, 16 images, {} points",
                                  model.Points3D().size()));
  EXPECT_EQ(result.num_priors, 0u);
  EXPECT_EQ(NavBundleAdjustmentJson(FixedWeight(2.0), result,
                                    model)["run"]["strategy"],
            "none (no priors)");
}

// --nav: rows are checked against the model's images, which get priors.
TEST(NavBundleAdjustmentController, LoadsThePriorsOfTheNavigation) {
  const fs::path dir = testing::FreshTestDir("uw_nav_ba_controller");
  const test::TestScene scene = SmallScene();
  NavBundleAdjustmentControllerOptions options = FixedWeight(2.0);
  options.priors.nav.nav_path = WriteNav(scene, dir);
  Reconstruction model = ModelInItsOwnFrame(scene);
  std::vector<std::string> lines;
  const NavBundleAdjustmentResult result =
      AdjustModelWithNavigation(options, &model, Into(&lines));
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[2], "World frame: the log's x,y,z (m)");
  EXPECT_EQ(lines[1],
            "Priors: 16 images (0 rows of images not in the model, left out)");
  EXPECT_EQ(result.num_priors, 16u);
  EXPECT_LT(test::CameraCenterRmse(model, scene.truth), 0.25);

  // A mapper rarely registers every image: a row of another image is left
  // out and counted.
  options.priors.nav.nav_path =
      WriteNav(scene, dir, "stray.png,99,1,0,0,3,0,0,0,0.3,0.3,0.3,1,1,1\n");
  Reconstruction with_stray = ModelInItsOwnFrame(scene);
  lines.clear();
  EXPECT_EQ(
      AdjustModelWithNavigation(options, &with_stray, Into(&lines)).num_priors,
      16u);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[2], "World frame: the log's x,y,z (m)");
  EXPECT_EQ(lines[1],
            "Priors: 16 images (1 rows of images not in the model, left out)");

  // A log none of whose rows names an image of the model is another
  // survey's.
  {
    std::ofstream out(dir / "other.csv");
    out << "image_name,time,dive,x,y,z,roll,pitch,yaw,std_x,std_y,std_z,"
           "std_roll,std_pitch,std_yaw\n"
           "other1.png,1,1,0,0,3,0,0,0,0.3,0.3,0.3,1,1,1\n"
           "other2.png,2,1,1,0,3,0,0,0,0.3,0.3,0.3,1,1,1\n";
  }
  options.priors.nav.nav_path = dir / "other.csv";
  Reconstruction untouched = ModelInItsOwnFrame(scene);
  ExpectErrorContaining([&] { AdjustModelWithNavigation(options, &untouched); },
                        "other.csv: none of its 2 rows names an image of the "
                        "model scene (16 images)");
}

// A log sampled at its own times, and image times that name an image the
// mapper did not register, taken an hour after the navigation ends: left
// out before it is placed (it has no prior to give), counted, and the run
// goes on.
TEST(NavBundleAdjustmentController, ImageTimesOfUnregisteredImagesAreLeftOut) {
  const fs::path dir = testing::FreshTestDir("uw_nav_ba_controller_times");
  const test::TestScene scene = SmallScene();
  const fs::path with_names = WriteNav(scene, dir);
  // The same log without its image names, and the names with their times.
  std::ifstream in(with_names);
  std::ofstream nav(dir / "series.csv");
  std::ofstream times(dir / "times.csv");
  times << "image_name,time\n";
  std::string line;
  std::getline(in, line);
  nav << line.substr(line.find(',') + 1) << "\n";
  while (std::getline(in, line)) {
    const size_t comma = line.find(',');
    nav << line.substr(comma + 1) << "\n";
    times << line.substr(0, line.find(',', comma + 1)) << "\n";
  }
  times << "unregistered.png,3600\n";
  nav.close();
  times.close();
  NavBundleAdjustmentControllerOptions options = FixedWeight(2.0);
  options.priors.nav.nav_path = dir / "series.csv";
  options.priors.nav.image_times_path = dir / "times.csv";
  Reconstruction model = ModelInItsOwnFrame(scene);
  std::vector<std::string> lines;
  EXPECT_EQ(AdjustModelWithNavigation(options, &model, Into(&lines)).num_priors,
            16u);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[2], "World frame: the log's x,y,z (m)");
  EXPECT_EQ(lines[1],
            "Priors: 16 images (1 rows of images not in the model, left out)");
  EXPECT_LT(test::CameraCenterRmse(model, scene.truth), 0.25);
}

TEST(NavBundleAdjustmentController, LCurveSweepsACopyOfTheModel) {
  const fs::path dir = testing::FreshTestDir("uw_nav_lcurve_controller");
  const test::TestScene scene = SmallScene();
  NavLCurveOptions options;
  options.input_path = "scene";
  options.adjuster = test::FixedIntrinsics();
  options.steps = 6;
  const Reconstruction model = ModelInItsOwnFrame(scene);
  ExpectErrorContaining([&] { SweepModelLCurve(options, model); },
                        "an L-curve needs navigation priors");

  options.priors.nav.nav_path = WriteNav(scene, dir);
  options.lambda_min = 0.1;
  options.lambda_max = 10.0;
  std::vector<std::string> lines;
  const NavLCurveResult result = SweepModelLCurve(options, model, Into(&lines));
  ASSERT_EQ(result.curve.points.size(), 6u);
  EXPECT_DOUBLE_EQ(result.curve.points.front().weight_px_per_m, 0.1);
  EXPECT_DOUBLE_EQ(result.curve.points.back().weight_px_per_m, 10.0);
  EXPECT_EQ(result.curve.noise_weight_px_per_m,
            result.noise_levels.weight_px_per_m);
  // The noise levels (with the log's times: both estimates, then the
  // one used), the sweep's title, a line per adjustment.
  ASSERT_EQ(lines.size(), 3u + 1u + 6u);
  EXPECT_NE(lines[1].find("from image to image"), std::string::npos)
      << lines[1];
  EXPECT_EQ(lines[3], "L-curve: 6 adjustments, lambda from 0.1 to 10 px/m");
  EXPECT_EQ(test::CameraCenterRmse(model, ModelInItsOwnFrame(scene)), 0.0);

  const std::string summary = FormatNavLCurveSummary(result);
  EXPECT_NE(summary.find(fmt::format("Noise levels: lambda = {:g} px/m\n",
                                     result.noise_levels.weight_px_per_m)),
            std::string::npos)
      << summary;
}

}  // namespace
}  // namespace uw
