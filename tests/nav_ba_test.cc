// uwcolmap bundle_adjuster on uwsim surveys with feature tracks from
// `uwsim observe` (known pixel noise, a model in an arbitrary frame):
// per-dive offsets against uwsim's true dive biases, soft rigs against the
// true relative poses, and the rejection of bad input.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "colmap_plugins/scene/model.h"
#include "colmap_plugins/scene/model_io.h"
#include "common/util/file.h"
#include "common/util/subprocess.h"
#include "tests/support/multi_dive.h"
#include "tests/support/process.h"

namespace uw {
namespace {

namespace fs = std::filesystem;
using testing::FreshTestDir;
using testing::Quoted;

const fs::path kUwsim = fs::path(UW_BIN_DIR) / "uwsim";
const fs::path kUwcolmap = fs::path(UW_BIN_DIR) / "uwcolmap";
const fs::path kFixtures = UW_FIXTURES_DIR;
// uwsim's camera on the vehicle (its default survey options).
const std::string kCameraOnVehicle =
    " --mount down --lever_arm 0.6,0,-0.3 --boresight 0.3,-0.5,0.8";
const std::string kFixedIntrinsics =
    " --BundleAdjustment.refine_focal_length 0"
    " --BundleAdjustment.refine_extra_params 0";

// uwsim generate + observe into dir/sim and dir/tracks.
void MakeSurvey(const fs::path& dir, const std::string& config,
                const std::string& survey) {
  const auto generate = RunProcess(
      Quoted(kUwsim) + " generate --survey " + survey + " --out " +
          Quoted(dir / "sim") + " --config " + Quoted(kFixtures / config),
      true);
  ASSERT_EQ(generate.exit_code, 0) << generate.output;
  const auto observe =
      RunProcess(Quoted(kUwsim) + " observe --sim " + Quoted(dir / "sim") +
                     " --output_path " + Quoted(dir / "tracks") +
                     " --pixel_sigma 0.5 --num_points 5000 --init perturbed",
                 true);
  ASSERT_EQ(observe.exit_code, 0) << observe.output;
}

nlohmann::json RunAdjuster(const fs::path& dir, const std::string& output,
                           const std::string& flags) {
  const auto result = RunProcess(
      Quoted(kUwcolmap) + " bundle_adjuster --input_path " +
          Quoted(dir / "tracks") + " --output_path " + Quoted(dir / output) +
          " --nav " + Quoted(dir / "sim" / "nav.csv") + kCameraOnVehicle +
          kFixedIntrinsics + " " + flags,
      true);
  EXPECT_EQ(result.exit_code, 0) << result.output;
  return nlohmann::json::parse(
      ReadFileToString(dir / output / "ba_report.json"));
}

// Acceptance 3 of issue 4: two dives whose navigation is off by 2-3 m
// relative to each other.
TEST(NavBundleAdjusterUwsim, DiveOffsetsRecoverTheTrueBiases) {
  const fs::path dir = FreshTestDir("uw_nav_ba_multi_dive");
  MakeSurvey(dir, "nav_ba_multi_dive.json", "multi_dive");
  const nlohmann::json sim =
      nlohmann::json::parse(ReadFileToString(dir / "sim/truth/sim.json"));
  const auto& biases = sim["truth"]["dive_biases_m"];
  const Eigen::Vector3d bias(
      biases[1][0].get<double>() - biases[0][0].get<double>(),
      biases[1][1].get<double>() - biases[0][1].get<double>(),
      biases[1][2].get<double>() - biases[0][2].get<double>());

  // lambda = sigma_v / sigma_n = 0.5 px / 0.1 m.
  const nlohmann::json with =
      RunAdjuster(dir, "with", "--Nav.weight 5 --Dive.offsets 1");
  const nlohmann::json without = RunAdjuster(dir, "without", "--Nav.weight 5");

  const nlohmann::json& offset = with["dive_offsets"][1];
  ASSERT_EQ(offset["dive"], 2);
  ASSERT_TRUE(offset.contains("sigma_m")) << with["covariance_note"];
  // The offset is added to dive 2's navigation: it estimates -bias.
  Eigen::Vector3d error;
  Eigen::Vector3d sigma;
  for (int i = 0; i < 3; ++i) {
    error(i) = offset["offset_m"][i].get<double>() + bias(i);
    sigma(i) = offset["sigma_m"][i].get<double>();
  }
  const auto mean_error = [](const nlohmann::json& report, int dive) {
    const nlohmann::json& entry = report["prior_residuals_by_dive"][dive - 1];
    return Eigen::Vector3d(entry["mean_error_m"][0].get<double>(),
                           entry["mean_error_m"][1].get<double>(),
                           entry["mean_error_m"][2].get<double>());
  };
  const Eigen::Vector3d split = mean_error(without, 2) - mean_error(without, 1);
  std::cout << "[ figures ] true relative bias " << bias.transpose()
            << " m; offset error " << error.transpose() * 100 << " cm, 1-sigma "
            << sigma.transpose() * 100
            << " cm; prior residual RMS with offsets "
            << with["prior_residual_rms_m"] << " m, without "
            << without["prior_residual_rms_m"]
            << " m; without offsets the dives' mean residuals differ by "
            << split.transpose() << " m; reprojection MS with "
            << with["final_cost"]["reprojection"]["mean_squared"]
            << " px^2, without "
            << without["final_cost"]["reprojection"]["mean_squared"]
            << " px^2\n";
  EXPECT_GT(bias.head<2>().norm(), 2.0);
  EXPECT_LT(error.norm(), 0.05);
  for (int i = 0; i < 3; ++i) EXPECT_LT(std::abs(error(i)), 3.0 * sigma(i));
  // Without offsets the contradiction shows in the report: the prior
  // residuals grow, and their means per dive split along the bias (the
  // model sits between the dives' navigation, which pull opposite ways).
  // Under Eq. 2's weighting the model would also bend to meet both
  // (reprojection error up); the likelihood keeps the images' shape.
  EXPECT_GT(without["prior_residual_rms_m"].get<double>(),
            3.0 * with["prior_residual_rms_m"].get<double>());
  EXPECT_GT(-split.dot(bias) / bias.squaredNorm(), 0.3);
}

// Issue 17: three dives 1.2 m apart under 7 cm of USBL noise (uwsim config
// `fixture`), adjusted with default flags and --Dive.offsets 1: converged,
// the offsets within 3 of their sigmas of the biases, and, with
// `noise_estimate_holds`, sigma_n within 1.5x of the realised noise.
testing::MultiDiveChain ExpectThreeDivesFused(const std::string& fixture,
                                              const std::string& name,
                                              bool noise_estimate_holds) {
  const testing::MultiDiveChain chain = testing::RunMultiDiveChain(
      UW_BIN_DIR, kFixtures / fixture, FreshTestDir(name));
  EXPECT_EQ(chain.exit_code, 0) << chain.output;
  EXPECT_EQ(chain.termination, "CONVERGENCE");
  std::cout << "[ figures ] " << fixture << ": sigma_n " << chain.nav_sigma_m
            << " m against " << chain.realised_nav_m << " m realised; "
            << chain.iterations << " iterations;";
  if (noise_estimate_holds) {
    EXPECT_LT(std::abs(std::log(chain.nav_sigma_m / chain.realised_nav_m)),
              std::log(1.5));
  }
  EXPECT_EQ(chain.dives, (std::vector<int>{2, 3}));
  for (size_t d = 0; d < chain.dives.size(); ++d) {
    std::cout << " dive " << chain.dives[d] << " offset error "
              << chain.offset_errors[d].transpose() << " m, "
              << chain.offset_errors[d]
                     .cwiseQuotient(chain.offset_sigmas[d])
                     .transpose()
              << " sigma";
    for (int k = 0; k < 3; ++k) {
      EXPECT_LT(std::abs(chain.offset_errors[d](k)),
                3.0 * chain.offset_sigmas[d](k))
          << "dive " << chain.dives[d] << " axis " << k;
    }
  }
  std::cout << "\n";
  return chain;
}

// On the vent. Until 2026-12-07 the robust initial alignment took one dive
// and refused the log as paired with another time ("only 9 of the 24
// positions agree"), and the noise estimate fitted the offsets and the
// similarity in turn (on the scarp: 100 iterations, NO_CONVERGENCE, exit
// 0, sigma_n 4.9x the realised noise).
TEST(NavBundleAdjusterUwsim, ThreeDivesFarApartConvergeWithDefaultFlags) {
  const testing::MultiDiveChain chain = ExpectThreeDivesFused(
      "nav_ba_three_dives.json", "uw_nav_ba_three_dives", true);
  EXPECT_TRUE(chain.warnings.empty()) << chain.output;
  // The model's frame beside it: the log's own x,y,z here.
  const nlohmann::json frame = nlohmann::json::parse(
      ReadFileToString(chain.output_dir / "world_frame.json"));
  EXPECT_EQ(frame.at("origin"), nullptr);
  EXPECT_EQ(frame.at("description"), "the log's x,y,z (m)");
}

// On the seafloor, whose third dive shares no point that 3 images see with
// the other two: the noise estimate leaves its images out, the report says
// that dive 3's offset is its prior's, and every offset's sigma is that of
// the problem solved (the priors as weighted). What does not hold here:
// sigma_n stays 14x the realised noise, since the first two dives, tied
// by few points, do not make an images-only model that is a similarity of
// the truth, even from one image to the next (differences over 1 image
// 3.0x the stated sigmas, over 2 images 7.8x). The estimate then keeps the
// similarity's residuals, and a warning says why. Before the sigmas
// followed the weighting, dive 2's offset was 1.3 m off at +- 0.29 m (4.6
// sigma).
TEST(NavBundleAdjusterUwsim, ADiveTheImagesDoNotTieIsNamed) {
  const testing::MultiDiveChain chain = ExpectThreeDivesFused(
      "nav_ba_three_dives_apart.json", "uw_nav_ba_three_dives_apart", false);
  const std::string warnings = nlohmann::json(chain.warnings).dump();
  EXPECT_NE(warnings.find("dive 3: none of its 20 images"), std::string::npos)
      << warnings;
  EXPECT_NE(warnings.find("the navigation's noise is estimated from the "
                          "other 33"),
            std::string::npos)
      << warnings;
  EXPECT_NE(warnings.find("differ more over 2 images than over 1"),
            std::string::npos)
      << warnings;
}

// Relative pose of each rig camera's image to the reference camera's image
// of the same frame (same name after the camK/ folder), estimated vs true.
struct RelativePoseErrors {
  double translation_rms_m = 0.0;
  double rotation_rms_deg = 0.0;
  int num_pairs = 0;
};

RelativePoseErrors MeasureRigErrors(const Reconstruction& model,
                                    const Reconstruction& truth) {
  const auto find = [](const Reconstruction& r, const std::string& name) {
    for (const Image& image : r.Images()) {
      if (image.name == name) return &image;
    }
    return static_cast<const Image*>(nullptr);
  };
  const auto relative = [](const Image& ref, const Image& cam) {
    Rigid3d cam_from_ref;
    cam_from_ref.rotation = cam.cam_from_world.rotation.normalized() *
                            ref.cam_from_world.rotation.normalized().inverse();
    cam_from_ref.translation =
        cam.cam_from_world.translation -
        cam_from_ref.rotation * ref.cam_from_world.translation;
    return cam_from_ref;
  };
  RelativePoseErrors errors;
  double t2 = 0.0;
  double r2 = 0.0;
  for (const Image& image : truth.Images()) {
    if (image.name.rfind("cam1/", 0) == 0) continue;
    const std::string ref_name = "cam1/" + image.name.substr(5);
    const Image* true_ref = find(truth, ref_name);
    const Image* ref = find(model, ref_name);
    const Image* cam = find(model, image.name);
    if (true_ref == nullptr || ref == nullptr || cam == nullptr) continue;
    const Rigid3d expected = relative(*true_ref, image);
    const Rigid3d estimated = relative(*ref, *cam);
    t2 += (expected.translation - estimated.translation).squaredNorm();
    const double angle =
        Eigen::AngleAxisd(expected.rotation.inverse() * estimated.rotation)
            .angle();
    r2 += std::pow(angle * 180.0 / M_PI, 2);
    ++errors.num_pairs;
  }
  errors.translation_rms_m = std::sqrt(t2 / errors.num_pairs);
  errors.rotation_rms_deg = std::sqrt(r2 / errors.num_pairs);
  return errors;
}

// Acceptance 4 of issue 4: a 3-camera rig whose cameras fire 20 and 50 ms
// after the reference one.
TEST(NavBundleAdjusterUwsim, SoftRigConstraintsFixRelativePoses) {
  const fs::path dir = FreshTestDir("uw_nav_ba_rig");
  MakeSurvey(dir, "nav_ba_rig.json", "lawnmower");
  const Reconstruction truth = ReadModel(dir / "sim/truth");
  const std::string common =
      "--Nav.weight 0.5 --image_times " + Quoted(dir / "sim/image_times.csv");
  // truth/rig.json states no sigma; give the calibration sigmas uwsim uses.
  const std::string rig =
      " --Rig.rotation_sigma 0.05 --Rig.translation_sigma "
      "0.002 --Rig.config ";
  RunAdjuster(dir, "no_rig", common);
  RunAdjuster(dir, "synchronised",
              common + rig + Quoted(dir / "sim/truth/rig.json") +
                  " --Rig.interpolate 0");
  RunAdjuster(dir, "interpolated",
              common + rig + Quoted(dir / "sim/truth/rig.json"));
  RunAdjuster(dir, "calibrated", common + rig + Quoted(dir / "sim/rig.json"));

  std::map<std::string, RelativePoseErrors> errors;
  for (const std::string name :
       {"no_rig", "synchronised", "interpolated", "calibrated"}) {
    errors[name] = MeasureRigErrors(ReadModel(dir / name), truth);
    std::cout << "[ figures ] rig, " << name << ": relative pose error RMS "
              << errors[name].translation_rms_m * 1000 << " mm, "
              << errors[name].rotation_rms_deg << " deg over "
              << errors[name].num_pairs << " image pairs\n";
  }
  EXPECT_EQ(errors["interpolated"].num_pairs, 66);
  EXPECT_LT(errors["interpolated"].translation_rms_m, 0.002);
  EXPECT_LT(errors["interpolated"].rotation_rms_deg, 0.05);
  EXPECT_LT(errors["interpolated"].translation_rms_m,
            0.5 * errors["no_rig"].translation_rms_m);
  EXPECT_LT(errors["interpolated"].rotation_rms_deg,
            0.5 * errors["no_rig"].rotation_rms_deg);
  // Pairing a late camera with the reference image alone reads the
  // vehicle's motion over 20-50 ms as rig error.
  EXPECT_LT(errors["interpolated"].translation_rms_m,
            0.5 * errors["synchronised"].translation_rms_m);
}

// Acceptance 6 of issue 4: bad input gives a clear error and writes
// nothing.
TEST(NavBundleAdjusterUwsim, BadInputIsRejectedAndNothingIsWritten) {
  const fs::path dir = FreshTestDir("uw_nav_ba_bad_input");
  MakeSurvey(dir, "nav_ba_rig.json", "lawnmower");
  const std::string nav_text = ReadFileToString(dir / "sim/nav.csv");
  std::vector<std::string> lines;
  {
    std::istringstream in(nav_text);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
  }
  const auto join = [](const std::vector<std::string>& rows) {
    std::string text;
    for (const std::string& row : rows) text += row + "\n";
    return text;
  };
  const auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    return dir / name;
  };
  // Field `index` (0-based) of a CSV row replaced.
  const auto with_field = [](const std::string& row, int index,
                             const std::string& value) {
    size_t start = 0;
    for (int i = 0; i < index; ++i) start = row.find(',', start) + 1;
    const size_t end = row.find(',', start);
    return row.substr(0, start) + value + row.substr(end);
  };
  // Lines 1-2: a comment and the header; data rows from line 3 on.
  std::vector<std::string> nan_rows = lines;
  nan_rows[2] = with_field(nan_rows[2], 3, "nan");  // x of line 3
  // A row of an image the model lacks is left out (a mapper rarely
  // registers every image), but a log naming none of its images is another
  // survey's.
  std::vector<std::string> other_rows = lines;
  for (size_t i = 2; i < other_rows.size(); ++i) {
    other_rows[i] =
        with_field(other_rows[i], 0, "other/" + std::to_string(i) + ".png");
  }
  std::vector<std::string> backwards_rows = lines;
  std::swap(backwards_rows[3], backwards_rows[4]);  // lines 4 and 5
  const std::vector<std::string> two_rows(lines.begin(), lines.begin() + 4);
  std::string unknown_camera_rig = ReadFileToString(dir / "sim/rig.json");
  unknown_camera_rig.replace(unknown_camera_rig.rfind("\"camera_id\": 3"), 14,
                             "\"camera_id\": 9");

  struct Case {
    std::string name;
    std::string flags;
    std::string message;
  };
  const std::string times =
      " --image_times " + Quoted(dir / "sim/image_times.csv");
  const std::vector<Case> cases = {
      {"nav naming no image of the model",
       "--nav " + Quoted(write("other.csv", join(other_rows))),
       "other.csv: none of its"},
      {"NaN", "--nav " + Quoted(write("nan.csv", join(nan_rows))), "nan.csv:3"},
      {"time going backwards",
       "--nav " + Quoted(write("back.csv", join(backwards_rows))),
       "back.csv:5"},
      {"rig.json naming an unknown camera",
       "--nav " + Quoted(dir / "sim/nav.csv") + times + " --Rig.config " +
           Quoted(write("rig9.json", unknown_camera_rig)),
       "camera 9"},
      {"fewer than 3 priors",
       "--nav " + Quoted(write("two.csv", join(two_rows))), "at least 3"},
  };
  for (const Case& c : cases) {
    const fs::path out = dir / ("out_" + std::to_string(&c - cases.data()));
    const auto result = RunProcess(
        Quoted(kUwcolmap) + " bundle_adjuster --input_path " +
            Quoted(dir / "tracks") + " --output_path " + Quoted(out) + " " +
            c.flags + kCameraOnVehicle + " --Nav.weight 1",
        true);
    std::cout << "[ figures ] " << c.name << ": exit " << result.exit_code
              << ", " << result.output.substr(result.output.find("ERROR"))
              << "";
    EXPECT_EQ(result.exit_code, 1) << c.name << "\n" << result.output;
    EXPECT_NE(result.output.find("ERROR"), std::string::npos) << c.name;
    EXPECT_NE(result.output.find(c.message), std::string::npos)
        << c.name << "\n"
        << result.output;
    EXPECT_FALSE(fs::exists(out)) << c.name;
  }
}

}  // namespace
}  // namespace uw
