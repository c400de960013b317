// laserscale end to end on the default uwsim survey reconstructed by stock
// colmap (fixture uwsim_survey), with its laser images added to a copy of
// the database by stock colmap (fixture laser_images,
// scripts/add_laser_images.sh).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <fstream>
#include <map>
#include <optional>

#include <nlohmann/json.hpp>

#include "colmap_plugins/align/similarity.h"
#include "colmap_plugins/scene/model_io.h"
#include "common/mesh/mesh.h"
#include "common/util/file.h"
#include "common/util/subprocess.h"
#include "laserscale/laser_poses_io.h"
#include "laserscale/spots_io.h"
#include "tests/support/process.h"
#include "tests/support/uwsim_survey.h"

namespace uw {
namespace {

namespace fs = std::filesystem;
using testing::FreshTestDir;
using testing::Quoted;

const fs::path kSurveyDir = UW_SURVEY_DIR;
const fs::path kLaserDir = UW_LASER_DIR;
const fs::path kLaserscale = fs::path(UW_BIN_DIR) / "laserscale";
const fs::path kUwcolmap = fs::path(UW_BIN_DIR) / "uwcolmap";

std::string RunLaserscale(const std::string& command) {
  const auto result = RunProcess(command, true);
  EXPECT_EQ(result.exit_code, 0) << command << "\n" << result.output;
  return result.output;
}

Rigid3d PoseFromJson(const nlohmann::json& json) {
  Rigid3d pose;
  const auto& q = json.at("qvec");
  pose.rotation = Eigen::Quaterniond(q[0].get<double>(), q[1].get<double>(),
                                     q[2].get<double>(), q[3].get<double>());
  const auto& t = json.at("tvec");
  pose.translation = Eigen::Vector3d(t[0].get<double>(), t[1].get<double>(),
                                     t[2].get<double>());
  return pose;
}

// The similarity that takes stock colmap's model of the survey to the
// truth, fitted to the survey images' camera centres.
SimilarityResult TruthFromModel(const Reconstruction& model,
                                const Reconstruction& truth) {
  std::map<std::string, Eigen::Vector3d> true_centres;
  for (const Image& image : truth.Images()) {
    true_centres[image.name] = image.ProjectionCenter();
  }
  std::vector<Eigen::Vector3d> src;
  std::vector<Eigen::Vector3d> dst;
  for (const Image& image : model.Images()) {
    src.push_back(image.ProjectionCenter());
    dst.push_back(true_centres.at(image.name));
  }
  SimilarityOptions options;
  options.robust = false;
  return EstimateSimilarity(src, dst, nullptr, options);
}

std::string Localize(const fs::path& poses,
                     const fs::path& model = kSurveyDir / "sparse/0") {
  return RunLaserscale(kLaserscale.string() + " localize --database_path " +
                       Quoted(kLaserDir / "database.db") + " --input_path " +
                       Quoted(model) + " --image_list_path " +
                       Quoted(kLaserDir / "laser_list.txt") + " --out " +
                       Quoted(poses));
}

// The true surface in the frame of stock colmap's model.
void WriteTrueSurfaceInModelFrame(const fs::path& path) {
  const fs::path sim = kSurveyDir / "sim";
  const Sim3d model_from_truth =
      TruthFromModel(ReadModel(kSurveyDir / "sparse/0"),
                     ReadModel(sim / "truth"))
          .b_from_a.Inverse();
  TriangleMesh surface = ReadPly(sim / "truth/mesh.ply");
  for (Eigen::Vector3d& vertex : surface.vertices) {
    vertex = model_from_truth * vertex;
  }
  WritePly(surface, path, "test surface in the model's frame");
}

// Acceptance 5: each laser image localized against stock colmap's model,
// mapped into the truth's frame by the similarity of the survey images'
// centres, lies within 1 cm and 0.05 deg of its true pose.
TEST(Laserscale, LocalizesLaserImagesAgainstStockColmapWithinACentimetre) {
  const fs::path dir = FreshTestDir("uw_laserscale_localize");
  Localize(dir / "poses.json");
  const std::vector<LocalizedImage> poses =
      ReadLaserPosesJson(dir / "poses.json");
  const Reconstruction model = ReadModel(kSurveyDir / "sparse/0");
  const Reconstruction truth = ReadModel(kSurveyDir / "sim/truth");
  const SimilarityResult alignment = TruthFromModel(model, truth);
  const Sim3d& truth_from_model = alignment.b_from_a;
  std::cout << "model vs truth: survey camera centres RMS "
            << 1000.0 * alignment.rms_m << " mm after the similarity\n";
  std::map<std::string, Eigen::Quaterniond> true_rotations;
  for (const Image& image : truth.Images()) {
    true_rotations[image.name] = image.cam_from_world.rotation.normalized();
  }
  double max_model_angle_deg = 0.0;
  for (const Image& image : model.Images()) {
    const Eigen::Quaterniond cam_from_truth =
        image.cam_from_world.rotation.normalized() *
        truth_from_model.rotation.conjugate();
    max_model_angle_deg =
        std::max(max_model_angle_deg,
                 cam_from_truth.angularDistance(true_rotations.at(image.name)) *
                     180.0 / M_PI);
  }
  std::cout << "model vs truth: survey camera rotations up to "
            << max_model_angle_deg << " deg off\n";

  const nlohmann::json laser_truth = nlohmann::json::parse(
      ReadFileToString(kSurveyDir / "sim/truth/laser_images.json"));
  std::map<std::string, Rigid3d> true_poses;
  std::map<std::string, std::string> neighbour;  // the survey image before
  for (const auto& image : laser_truth.at("images")) {
    const std::string name = image.at("name").get<std::string>();
    true_poses[name] = PoseFromJson(image.at("cam_from_world"));
    char survey_name[32];
    std::snprintf(survey_name, sizeof(survey_name), "%05d.png",
                  image.at("survey_image_index").get<int>());
    neighbour[name] = survey_name;
  }
  std::map<std::string, Eigen::Quaterniond> model_rotations;
  for (const Image& image : model.Images()) {
    model_rotations[image.name] = image.cam_from_world.rotation.normalized();
  }
  ASSERT_EQ(poses.size(), true_poses.size());
  double max_centre_m = 0.0;
  double max_angle_deg = 0.0;
  double max_relative_deg = 0.0;
  for (const LocalizedImage& pose : poses) {
    ASSERT_TRUE(pose.success) << pose.name << ": " << pose.problem;
    EXPECT_GT(pose.inliers.size(), 100u) << pose.name;
    const Rigid3d& truth_pose = true_poses.at(pose.name);
    const Eigen::Vector3d centre =
        truth_from_model * pose.cam_from_world.Inverse().translation;
    const Eigen::Vector3d true_centre = truth_pose.Inverse().translation;
    const Eigen::Quaterniond cam_from_truth =
        pose.cam_from_world.rotation.normalized() *
        truth_from_model.rotation.conjugate();
    const double angle_deg =
        cam_from_truth.angularDistance(truth_pose.rotation.normalized()) *
        180.0 / M_PI;
    const double centre_m = (centre - true_centre).norm();
    // The rotation relative to the survey image before it, in the model and
    // in the truth: what localization adds to the model's own error.
    const Eigen::Quaterniond relative_model =
        pose.cam_from_world.rotation.normalized() *
        model_rotations.at(neighbour.at(pose.name)).conjugate();
    const Eigen::Quaterniond relative_truth =
        truth_pose.rotation.normalized() *
        true_rotations.at(neighbour.at(pose.name)).conjugate();
    const double relative_deg =
        relative_model.angularDistance(relative_truth) * 180.0 / M_PI;
    max_relative_deg = std::max(max_relative_deg, relative_deg);
    std::cout << pose.name << ": " << pose.inliers.size() << " inliers, RMS "
              << pose.rms_error_px << " px, centre " << 1000.0 * centre_m
              << " mm, rotation " << angle_deg
              << " deg off the truth; relative to " << neighbour.at(pose.name)
              << " " << relative_deg << " deg off\n";
    max_centre_m = std::max(max_centre_m, centre_m);
    max_angle_deg = std::max(max_angle_deg, angle_deg);
  }
  // The centres to 1 cm in the truth's frame; the rotations to 0.05 deg
  // relative to the model's images (the model's own rotations are up to
  // ~0.1 deg off the truth, which no localization against it can undo).
  EXPECT_LT(max_centre_m, 0.01);
  EXPECT_LT(max_relative_deg, 0.05);
  EXPECT_LT(max_angle_deg, max_model_angle_deg + 0.05);
}

// The whole chain on the default survey: detect the spots, localize the
// laser images, estimate the scale (FUM, Monte Carlo) and apply it. The
// true scale of stock colmap's model is the similarity's to the truth.
// With the true surface moved into the model's frame the estimate must be
// right within its own 95 % interval; with the sparse heightfield (the
// stand-in until a dense mesh) the surface's coarseness biases it.
TEST(Laserscale, DetectLocalizeEstimateApplyOnTheDefaultSurvey) {
  const fs::path dir = FreshTestDir("uw_laserscale_chain");
  const fs::path sim = kSurveyDir / "sim";
  RunLaserscale(kLaserscale.string() + " detect --images " +
                Quoted(sim / "laser_images") + " --lasers " +
                Quoted(sim / "lasers.json") + " --input_path " +
                Quoted(kSurveyDir / "sparse/0") + " --out " +
                Quoted(dir / "spots.json") + " --overlays " +
                Quoted(dir / "overlays"));
  Localize(dir / "poses.json");
  const Reconstruction model = ReadModel(kSurveyDir / "sparse/0");
  const Sim3d truth_from_model =
      TruthFromModel(model, ReadModel(sim / "truth")).b_from_a;
  const double true_scale = truth_from_model.scale;
  WriteTrueSurfaceInModelFrame(dir / "true_surface.ply");
  RunLaserscale(kLaserscale.string() + " sparse_surface --input_path " +
                Quoted(kSurveyDir / "sparse/0") + " --output_path " +
                Quoted(dir / "sparse_surface.ply"));
  for (const std::string surface : {"true_surface", "sparse_surface"}) {
    const fs::path report = dir / ("report_" + surface);
    RunLaserscale(
        kLaserscale.string() + " estimate --mesh " +
        Quoted(dir / (surface + ".ply")) + " --poses " +
        Quoted(dir / "poses.json") + " --spots " + Quoted(dir / "spots.json") +
        " --lasers " + Quoted(sim / "lasers.json") + " --overlays " +
        Quoted(dir / "overlays") + " --mc 2000 --out " + Quoted(report));
    const nlohmann::json scale =
        nlohmann::json::parse(ReadFileToString(report / "scale.json"));
    const double s = scale.at("scale").get<double>();
    const double low = scale.at("ci95")[0].get<double>();
    const double high = scale.at("ci95")[1].get<double>();
    std::cout << surface << ": s = " << s << " [" << low << ", " << high
              << "], true " << true_scale << ": error "
              << 100.0 * (s / true_scale - 1.0) << " %, "
              << scale.at("num_accepted") << " of " << scale.at("num_images")
              << " images\n";
    EXPECT_GE(scale.at("num_accepted").get<int>(), 5) << surface;
    if (surface == "true_surface") {
      EXPECT_LT(std::abs(s / true_scale - 1.0), 0.005);
      EXPECT_LE(low, true_scale);
      EXPECT_GE(high, true_scale);
    } else {
      EXPECT_LT(std::abs(s / true_scale - 1.0), 0.02);
    }
    EXPECT_TRUE(fs::exists(report / "index.html"));
    EXPECT_TRUE(fs::exists(report / "scales.png"));
  }
  // apply: the scaled model's camera centres are the truth's up to a rigid
  // motion, to the scale's own error.
  RunLaserscale(kLaserscale.string() + " apply --input_path " +
                Quoted(kSurveyDir / "sparse/0") + " --scale " +
                Quoted(dir / "report_true_surface/scale.json") +
                " --output_path " + Quoted(dir / "metric"));
  const Reconstruction metric = ReadModel(dir / "metric");
  const double remaining =
      TruthFromModel(metric, ReadModel(sim / "truth")).b_from_a.scale;
  EXPECT_NEAR(remaining, 1.0, 0.005);
}

// Issue 16, item 2: with the model's covariance draws the Monte Carlo also
// re-samples the model, reports every source's share of the variance, and
// for a navigation-fused model the z-score against the navigation's scale;
// apply warns when that disagrees; draws or poses of another model are
// refused.
TEST(Laserscale, EstimateSamplesTheModelFromItsCovariance) {
  const fs::path dir = FreshTestDir("uw_laserscale_covariance");
  const fs::path sim = kSurveyDir / "sim";
  const fs::path model = kSurveyDir / "sparse/0";
  RunLaserscale(kLaserscale.string() + " detect --images " +
                Quoted(sim / "laser_images") + " --lasers " +
                Quoted(sim / "lasers.json") + " --input_path " + Quoted(model) +
                " --out " + Quoted(dir / "spots.json"));
  Localize(dir / "poses.json");
  WriteTrueSurfaceInModelFrame(dir / "true_surface.ply");
  RunLaserscale(kUwcolmap.string() + " covariance_estimator --input_path " +
                Quoted(model) + " --output_path " + Quoted(dir / "cov") +
                " --Covariance.gauge held --Covariance.samples 100");
  const std::string estimate =
      kLaserscale.string() + " estimate --poses " + Quoted(dir / "poses.json") +
      " --spots " + Quoted(dir / "spots.json") + " --lasers " +
      Quoted(sim / "lasers.json") + " --mc 1000 --mesh " +
      Quoted(dir / "true_surface.ply");
  RunLaserscale(estimate + " --variance_shares 0 --out " +
                Quoted(dir / "exact"));
  const std::string output = RunLaserscale(
      estimate + " --covariance " + Quoted(dir / "cov") + " --input_path " +
      Quoted(model) + " --out " + Quoted(dir / "sampled"));
  std::cout << output;
  const nlohmann::json exact =
      nlohmann::json::parse(ReadFileToString(dir / "exact/scale.json"));
  const nlohmann::json sampled =
      nlohmann::json::parse(ReadFileToString(dir / "sampled/scale.json"));
  EXPECT_EQ(exact.at("model_draws").at("count"), 0);
  EXPECT_FALSE(exact.contains("variance_by_source"));
  EXPECT_EQ(sampled.at("model_draws").at("count"), 100);
  EXPECT_EQ(sampled.at("model_draws").at("gauge"), "held");
  EXPECT_FALSE(sampled.contains("navigation")) << "no priors, no z-score";
  // The model's error adds to the others: the interval widens (up to the
  // Monte Carlo's own noise), and the shares of independent sources sum
  // to about one.
  EXPECT_GE(sampled.at("sigma").get<double>(),
            0.98 * exact.at("sigma").get<double>());
  double share_sum = 0.0;
  for (const char* source : {"features", "spots", "calibration", "model"}) {
    ASSERT_TRUE(sampled.at("variance_by_source").contains(source)) << source;
    const double share =
        sampled["variance_by_source"][source].at("share").get<double>();
    EXPECT_GT(share, 0.0) << source;
    share_sum += share;
  }
  EXPECT_NEAR(share_sum, 1.0, 0.2);
  const double true_scale =
      TruthFromModel(ReadModel(model), ReadModel(sim / "truth")).b_from_a.scale;
  EXPECT_LE(sampled.at("ci95")[0].get<double>(), true_scale);
  EXPECT_GE(sampled.at("ci95")[1].get<double>(), true_scale);

  // The navigation-fused model with its covariance under the priors: the
  // laser scale against the navigation's own.
  const fs::path fused = dir / "fused";
  RunLaserscale(kUwcolmap.string() + " bundle_adjuster --input_path " +
                Quoted(model) + " --output_path " + Quoted(fused) + " --nav " +
                Quoted(sim / "nav.csv") + " " + testing::SurveyMountFlags(sim) +
                " --BA.covariance 1 --Covariance.samples 100");
  Localize(dir / "poses_fused.json", fused);
  RunLaserscale(kLaserscale.string() + " sparse_surface --input_path " +
                Quoted(fused) + " --output_path " + Quoted(dir / "fused.ply"));
  const std::string fused_estimate =
      kLaserscale.string() + " estimate --poses " +
      Quoted(dir / "poses_fused.json") + " --spots " +
      Quoted(dir / "spots.json") + " --lasers " + Quoted(sim / "lasers.json") +
      " --mc 500 --mesh " + Quoted(dir / "fused.ply") + " --covariance " +
      Quoted(fused / "covariance") + " --input_path " + Quoted(fused);
  std::cout << RunLaserscale(fused_estimate + " --out " +
                             Quoted(dir / "fused_report"));
  nlohmann::json fused_scale =
      nlohmann::json::parse(ReadFileToString(dir / "fused_report/scale.json"));
  const nlohmann::json& navigation = fused_scale.at("navigation");
  EXPECT_GT(navigation.at("log_scale_sigma").get<double>(), 0.0);
  const double z = navigation.at("z").get<double>();
  EXPECT_LT(std::abs(z), 3.0);
  EXPECT_EQ(navigation.at("consistent").get<bool>(), std::abs(z) <= 3.0);
  EXPECT_NEAR(z,
              (fused_scale.at("scale").get<double>() - 1.0) /
                  std::hypot(fused_scale.at("sigma").get<double>(),
                             navigation.at("log_scale_sigma").get<double>()),
              1e-9);
  // apply warns loudly on a scale that disagrees with the navigation.
  fused_scale["navigation"]["z"] = 4.25;
  fused_scale["navigation"]["consistent"] = false;
  std::ofstream(dir / "disagrees.json") << fused_scale.dump();
  const std::string applied = RunLaserscale(
      kLaserscale.string() + " apply --input_path " + Quoted(fused) +
      " --scale " + Quoted(dir / "disagrees.json") + " --output_path " +
      Quoted(dir / "applied"));
  EXPECT_NE(applied.find("WARNING"), std::string::npos) << applied;
  EXPECT_NE(applied.find("4.2 sigma"), std::string::npos) << applied;

  // Draws of another model, poses of another model, a version 1 poses.json,
  // --covariance alone: errors, and no report.
  nlohmann::json poses =
      nlohmann::json::parse(ReadFileToString(dir / "poses.json"));
  poses["version"] = 1;
  for (auto& image : poses["images"]) {
    if (!image.contains("inliers")) continue;
    for (auto& row : image["inliers"]) row.erase(5);
  }
  std::ofstream(dir / "poses_v1.json") << poses.dump();
  for (const auto& [flags, words] :
       std::vector<std::pair<std::string, std::string>>{
           {" --poses " + Quoted(dir / "poses.json") + " --covariance " +
                Quoted(dir / "cov") + " --input_path " + Quoted(fused),
            "adjusted since"},
           {" --poses " + Quoted(dir / "poses.json") + " --covariance " +
                Quoted(fused / "covariance") + " --input_path " + Quoted(fused),
            "another model"},
           {" --poses " + Quoted(dir / "poses_v1.json") + " --covariance " +
                Quoted(dir / "cov") + " --input_path " + Quoted(model),
            "version 1"},
           {" --poses " + Quoted(dir / "poses.json") + " --covariance " +
                Quoted(dir / "cov"),
            "--input_path"}}) {
    const fs::path out = dir / ("refused_" + std::to_string(words.size()));
    const auto result = RunProcess(
        kLaserscale.string() + " estimate --spots " +
            Quoted(dir / "spots.json") + " --lasers " +
            Quoted(sim / "lasers.json") + " --mc 50 --mesh " +
            Quoted(dir / "true_surface.ply") + flags + " --out " + Quoted(out),
        true);
    EXPECT_NE(result.exit_code, 0) << flags;
    EXPECT_NE(result.output.find(words), std::string::npos) << result.output;
    EXPECT_FALSE(fs::exists(out / "scale.json")) << flags;
  }
}

// Acceptance 7: bad input gives per-item flags or a clear error, never a
// NaN scale. Spots are the truth's pixels (the detector is tested
// elsewhere); one is moved outside its image.
TEST(Laserscale, EstimateFlagsBadItemsAndRefusesBadInputs) {
  const fs::path dir = FreshTestDir("uw_laserscale_bad_input");
  const fs::path sim = kSurveyDir / "sim";
  Localize(dir / "poses.json");
  const nlohmann::json truth =
      nlohmann::json::parse(ReadFileToString(sim / "truth/laser_images.json"));
  std::vector<ImageSpots> images;
  for (const auto& image : truth.at("images")) {
    ImageSpots spots;
    spots.name = image.at("name").get<std::string>();
    spots.setup = truth.at("setup").get<std::string>();
    for (const auto& spot : image.at("spots")) {
      DetectedSpot detected;
      detected.laser = spot.at("laser").get<std::string>();
      if (spot.at("visible").get<bool>()) {
        detected.detected = detected.stable = true;
        detected.detection_rate = 1.0;
        detected.pixel = Eigen::Vector2d(spot.at("pixel")[0].get<double>(),
                                         spot.at("pixel")[1].get<double>());
        detected.covariance = 0.04 * Eigen::Matrix2d::Identity();
      } else {
        detected.problem = "not visible";
      }
      spots.spots.push_back(detected);
    }
    images.push_back(spots);
  }
  images[0].spots[0].pixel = Eigen::Vector2d(-50.0, -50.0);
  std::ofstream(dir / "spots.json") << SpotsJsonText(images);
  const std::string estimate = kLaserscale.string() + " estimate --poses " +
                               Quoted(dir / "poses.json") + " --spots " +
                               Quoted(dir / "spots.json") + " --mc 200 --out " +
                               Quoted(dir / "report");
  RunLaserscale(kLaserscale.string() + " sparse_surface --input_path " +
                Quoted(kSurveyDir / "sparse/0") + " --output_path " +
                Quoted(dir / "surface.ply"));
  RunLaserscale(estimate + " --mesh " + Quoted(dir / "surface.ply") +
                " --lasers " + Quoted(sim / "lasers.json"));
  const std::string items = ReadFileToString(dir / "report/items.csv");
  EXPECT_NE(items.find("lies outside the 1024x768 image"), std::string::npos)
      << items;
  EXPECT_EQ(items.find("nan"), std::string::npos);
  const std::string scale = ReadFileToString(dir / "report/scale.json");
  EXPECT_EQ(scale.find("NaN"), std::string::npos);
  EXPECT_EQ(scale.find("nan"), std::string::npos);

  // An empty mesh, lasers without directions: clear errors, no report.
  std::ofstream(dir / "empty.ply")
      << "ply\nformat ascii 1.0\nelement vertex 0\nproperty double x\n"
         "property double y\nproperty double z\nelement face 0\n"
         "property list uchar int vertex_indices\nend_header\n";
  nlohmann::json lasers =
      nlohmann::json::parse(ReadFileToString(sim / "lasers.json"));
  lasers["setups"][0]["lasers"][1].erase("direction_in_cam");
  std::ofstream(dir / "no_direction.json") << lasers.dump();
  for (const auto& [flags, words] :
       std::vector<std::pair<std::string, std::string>>{
           {" --mesh " + Quoted(dir / "empty.ply") + " --lasers " +
                Quoted(sim / "lasers.json"),
            "no triangles"},
           {" --mesh " + Quoted(dir / "surface.ply") + " --lasers " +
                Quoted(dir / "no_direction.json"),
            "direction_in_cam"}}) {
    const auto result =
        RunProcess(estimate + "_" + std::to_string(words.size()) + flags, true);
    EXPECT_NE(result.exit_code, 0) << flags;
    EXPECT_NE(result.output.find(words), std::string::npos) << result.output;
  }
}

// Issue 17, acceptance 4, through the commands: uwsim worlds strewn with
// white shells, coloured debris and shiny objects, their laser images
// taken with laser L0 switched off. `laserscale detect` reports no stable
// spot for L0 nor away from a lit laser's spot, and finds the lit spots at
// least as often as without the colour test.
TEST(Laserscale, DetectFindsNoSpotOfASwitchedOffLaserAmongDistractors) {
  const fs::path dir = FreshTestDir("uw_laserscale_distractors");
  std::ofstream(dir / "config.json") << R"({
    "lasers": {"every_nth_image": 1, "switched_off": ["L0"]},
    "distractors": {"shells_per_m2": 30, "debris_per_m2": 15,
                    "shiny_per_m2": 10}
  })";
  for (const auto& [world, seed] :
       {std::pair("seafloor", 23), std::pair("vent", 5),
        std::pair("breakwater", 7)}) {
    const fs::path sim = dir / world;
    const auto generated = RunProcess(
        (fs::path(UW_BIN_DIR) / "uwsim").string() + " generate --config " +
            Quoted(dir / "config.json") + " --world " + world + " --seed " +
            std::to_string(seed) + " --max_images 16 --out " + Quoted(sim),
        true);
    ASSERT_EQ(generated.exit_code, 0) << generated.output;
    const nlohmann::json truth = nlohmann::json::parse(
        ReadFileToString(sim / "truth/laser_images.json"));
    const nlohmann::json sim_json =
        nlohmann::json::parse(ReadFileToString(sim / "truth/sim.json"));
    EXPECT_GT(sim_json.at("truth").at("num_distractors").get<int>(), 1000);
    // Per image and laser: the true pixel of a lit, visible spot; none for
    // a laser off or a spot the camera does not see.
    std::map<std::string, std::map<std::string, std::optional<Eigen::Vector2d>>>
        lit;
    for (const nlohmann::json& image : truth.at("images")) {
      for (const nlohmann::json& spot : image.at("spots")) {
        std::optional<Eigen::Vector2d>& pixel =
            lit[image.at("name").get<std::string>()]
               [spot.at("laser").get<std::string>()];
        if (spot.at("on").get<bool>() && spot.at("visible").get<bool>()) {
          pixel = Eigen::Vector2d(spot.at("pixel")[0].get<double>(),
                                  spot.at("pixel")[1].get<double>());
        }
      }
    }
    const auto detect = [&](const std::string& out, const std::string& flags) {
      RunLaserscale(kLaserscale.string() + " detect --images " +
                    Quoted(sim / "laser_images") + " --lasers " +
                    Quoted(sim / "lasers.json") + " --input_path " +
                    Quoted(sim / "truth") + " --out " + Quoted(sim / out) +
                    " " + flags);
      // False: stable where no lit spot is, or 3 px or more from it (the
      // detector's errors are < 1 px: that is something else on the beam).
      std::array<int, 3> counts{0, 0, 0};  // false stable, lit found, lit
      for (const ImageSpots& image : ReadSpotsJson(sim / out)) {
        for (const DetectedSpot& spot : image.spots) {
          const std::optional<Eigen::Vector2d>& pixel =
              lit.at(image.name).at(spot.laser);
          const bool found =
              spot.stable && pixel && (spot.pixel - *pixel).norm() < 3.0;
          counts[0] += spot.stable && !found;
          counts[1] += found;
          counts[2] += pixel.has_value();
        }
      }
      return counts;
    };
    const auto with = detect("spots.json", "");
    const auto without =
        detect("spots_no_colour.json", "--max_colour_angle_deg 180");
    std::cout << "[ figures ] " << world << ", switched-off L0 among "
              << sim_json.at("truth").at("num_distractors")
              << " distractors: " << with[0] << " false stable spots ("
              << without[0] << " without the colour test); lit spots found "
              << with[1] << " of " << with[2] << " (" << without[1]
              << " without)\n";
    EXPECT_EQ(with[0], 0) << world;
    EXPECT_GE(with[2], 20) << world;
    // Masking a spot of another colour lets the next on the beam be
    // tried: as many lit spots or more.
    EXPECT_GE(with[1], without[1]) << world;
  }
}

}  // namespace
}  // namespace uw
