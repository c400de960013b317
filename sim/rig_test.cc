#include "sim/rig.h"

#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "colmap_plugins/scene/model_io.h"
#include "common/util/error.h"
#include "common/util/file.h"
#include "sim/generate.h"
#include "sim/test_sim_config.h"

namespace uw::sim {
namespace {

namespace fs = std::filesystem;

Rigid3d Compose(const Rigid3d& c_from_b, const Rigid3d& b_from_a) {
  Rigid3d c_from_a;
  c_from_a.rotation = c_from_b.rotation * b_from_a.rotation;
  c_from_a.translation = c_from_b * b_from_a.translation;
  return c_from_a;
}

Rigid3d VehicleFromWorld(const SurveyStation& station) {
  Rigid3d world_from_vehicle;
  world_from_vehicle.rotation =
      Eigen::Quaterniond(WorldFromVehicleRotation(station.vehicle_rpy));
  world_from_vehicle.translation = station.vehicle_position;
  return world_from_vehicle.Inverse();
}

double PoseError(const Rigid3d& a, const Rigid3d& b) {
  return (a.Inverse().translation - b.Inverse().translation).norm() +
         a.rotation.normalized().angularDistance(b.rotation.normalized());
}

// One pass of 4 stations 1 s apart, turning and climbing, then a second.
std::vector<SurveyStation> Stations(const Rigid3d& vehicle_from_rig) {
  std::vector<SurveyStation> stations;
  for (int pass = 0; pass < 2; ++pass) {
    for (int i = 0; i < 4; ++i) {
      SurveyStation station;
      station.pass = pass;
      station.time_s = 10.0 * pass + i;
      station.vehicle_position = {0.5 * i, 3.0 * pass, 0.1 * i};
      station.vehicle_rpy = {0.02 * i, -0.01 * i, 0.05 * i + pass};
      station.cam_from_world =
          Compose(vehicle_from_rig.Inverse(), VehicleFromWorld(station));
      stations.push_back(station);
    }
  }
  return stations;
}

Rigid3d SomePose(double angle, const Eigen::Vector3d& axis,
                 const Eigen::Vector3d& translation) {
  Rigid3d pose;
  pose.rotation =
      Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized()));
  pose.translation = translation;
  return pose;
}

TEST(StationOfRigCamera, InterpolatesTheVehicleAlongItsLine) {
  const Rigid3d vehicle_from_rig =
      SomePose(2.0, {1, -1, 0.3}, {0.6, 0.0, -0.3});
  const std::vector<SurveyStation> stations = Stations(vehicle_from_rig);
  const Rigid3d cam_from_rig = SomePose(0.2, {0, 1, 0}, {-0.3, 0.01, 0.0});
  // No offset: the station's vehicle pose through the rig.
  const SurveyStation same =
      StationOfRigCamera(stations, 1, vehicle_from_rig, cam_from_rig, 0.0);
  EXPECT_LT(PoseError(same.cam_from_world,
                      Compose(cam_from_rig, stations[1].cam_from_world)),
            1e-12);
  // Half-way to the next station: mid position, mid attitude.
  const SurveyStation half =
      StationOfRigCamera(stations, 1, vehicle_from_rig, cam_from_rig, 0.5);
  EXPECT_DOUBLE_EQ(half.time_s, 1.5);
  EXPECT_NEAR((half.vehicle_position - Eigen::Vector3d(0.75, 0.0, 0.15)).norm(),
              0.0, 1e-12);
  const Eigen::Quaterniond q1(
      WorldFromVehicleRotation(stations[1].vehicle_rpy));
  const Eigen::Quaterniond q2(
      WorldFromVehicleRotation(stations[2].vehicle_rpy));
  const Eigen::Quaterniond mid(WorldFromVehicleRotation(half.vehicle_rpy));
  EXPECT_NEAR(mid.angularDistance(q1.slerp(0.5, q2)), 0.0, 1e-12);
  // The rig camera's pose is cam_from_rig after the reference camera's at
  // the same instant.
  const SurveyStation reference_half =
      StationOfRigCamera(stations, 1, vehicle_from_rig, Rigid3d(), 0.5);
  EXPECT_LT(PoseError(half.cam_from_world,
                      Compose(cam_from_rig, reference_half.cam_from_world)),
            1e-12);
  // Past the end of the first pass it extrapolates the last segment and
  // never borrows from the next pass.
  const SurveyStation past =
      StationOfRigCamera(stations, 3, vehicle_from_rig, cam_from_rig, 0.5);
  EXPECT_NEAR((past.vehicle_position - Eigen::Vector3d(1.75, 0.0, 0.35)).norm(),
              0.0, 1e-12);
  // A negative offset at the first station extrapolates backwards.
  const SurveyStation before =
      StationOfRigCamera(stations, 4, vehicle_from_rig, cam_from_rig, -0.2);
  EXPECT_NEAR(
      (before.vehicle_position - Eigen::Vector3d(-0.1, 3.0, -0.02)).norm(), 0.0,
      1e-12);
}

RigOptions StereoRig() {
  RigOptions rig;
  RigCameraOptions right;
  right.camera.model_id = CameraModelId::kPinhole;
  right.camera.width = 200;
  right.camera.height = 150;
  right.camera.params = {170.0, 170.0, 100.0, 75.0};
  right.cam_from_rig = SomePose(0.05, {0, 1, 0}, {-0.3, 0.0, 0.0});
  right.time_offset_s = 0.2;
  rig.cameras = {right};
  return rig;
}

TEST(RigOptions, JsonRoundTripsAndRejectsNonsense) {
  const RigOptions rig = StereoRig();
  const nlohmann::json json = rig;
  RigOptions read;
  json.get_to(read);
  EXPECT_EQ(nlohmann::json(read), json);
  EXPECT_NO_THROW(read.Check());
  nlohmann::json bad = json;
  bad["cameras"][0]["time_offset"] = 1.0;
  EXPECT_THROW(bad.get_to(read), Error);
  bad = json;
  bad["cameras"][0]["camera"]["model"] = "NOPE";
  EXPECT_THROW(bad.get_to(read), Error);
  bad = json;
  bad["cameras"][0]["cam_from_rig"]["qvec"] = {1, 0, 0};
  EXPECT_THROW(bad.get_to(read), Error);
  RigOptions slow = rig;
  slow.cameras[0].time_offset_s = 100.0;
  EXPECT_THROW(slow.Check(), Error);
}

TEST(RigJsonText, TruthIsExactCalibrationIsPerturbedBySigma) {
  const RigOptions rig = StereoRig();
  const nlohmann::json truth =
      nlohmann::json::parse(RigJsonText(rig, false, 1));
  ASSERT_EQ(truth.at("cameras").size(), 2u);
  EXPECT_EQ(truth["cameras"][1]["image_prefix"], "cam2/");
  EXPECT_EQ(truth["cameras"][1]["time_offset_s"], 0.2);
  const Rigid3d exact = PoseFromJson(truth["cameras"][1]["cam_from_rig"], "t");
  EXPECT_LT(PoseError(exact, rig.cameras[0].cam_from_rig), 1e-15);
  double sum_sq = 0.0;
  const int draws = 500;
  for (int seed = 0; seed < draws; ++seed) {
    const nlohmann::json calibrated =
        nlohmann::json::parse(RigJsonText(rig, true, seed));
    const Rigid3d pose =
        PoseFromJson(calibrated["cameras"][1]["cam_from_rig"], "c");
    sum_sq += (pose.translation - exact.translation).squaredNorm();
    EXPECT_EQ(calibrated["cameras"][1]["translation_sigma_m"], 0.002);
  }
  // Three axes of sigma 2 mm each; 500 draws: within 10 %.
  EXPECT_NEAR(std::sqrt(sum_sq / draws / 3.0), 0.002, 0.0002);
}

TEST(GenerateRig, WritesEveryCameraItsTimesAndTheRig) {
  SimConfig config = SmallSimConfig();
  config.survey_options.max_images = 4;
  config.lasers.every_nth_image = 2;
  config.rig = StereoRig();
  const fs::path out =
      fs::temp_directory_path() / ("uw_rig_" + std::to_string(getpid()));
  fs::remove_all(out);
  const GenerateSummary summary = Generate(config, out);
  EXPECT_EQ(summary.num_images, 8u);
  const Reconstruction model = ReadModel(out / "truth");
  ASSERT_EQ(model.Cameras().size(), 2u);
  ASSERT_EQ(model.Images().size(), 8u);
  for (const Image& image : model.Images()) {
    const std::string folder = image.camera_id == 1 ? "cam1/" : "cam2/";
    EXPECT_EQ(image.name.substr(0, 5), folder);
    EXPECT_TRUE(fs::exists(out / "images" / image.name)) << image.name;
  }
  // Each cam2 image: cam_from_rig after cam1's pose 0.2 s later, which lies
  // on the line between cam1's stations (for the first three).
  const auto by_name = [&](const std::string& name) -> const Image& {
    for (const Image& image : model.Images()) {
      if (image.name == name) return image;
    }
    throw Error("no image " + name);
  };
  const Image& left = by_name("cam1/00000.png");
  const Image& right = by_name("cam2/00000.png");
  const Image& next = by_name("cam1/00001.png");
  const Eigen::Vector3d left_centre = left.cam_from_world.Inverse().translation;
  const Eigen::Vector3d next_centre = next.cam_from_world.Inverse().translation;
  const Eigen::Vector3d right_centre =
      right.cam_from_world.Inverse().translation;
  const std::string times = ReadFileToString(out / "image_times.csv");
  EXPECT_NE(times.find("cam2/00000.png,0.20000000000000001"), std::string::npos)
      << times;
  // The 0.3 m baseline, give or take the vehicle's motion in 0.2 s (the
  // stations are 1 s or more apart).
  const double motion = 0.2 * (next_centre - left_centre).norm();
  EXPECT_NEAR((right_centre - left_centre).norm(), 0.3, motion + 1e-9);
  EXPECT_GT(motion, 0.01);
  EXPECT_NE(ReadFileToString(out / "rig.json"),
            ReadFileToString(out / "truth" / "rig.json"));
  EXPECT_NE(ReadFileToString(out / "nav.csv").find("cam1/00003.png"),
            std::string::npos);
  EXPECT_TRUE(fs::exists(out / "laser_images" / "cam1" / "L00001.png"));
  fs::remove_all(out);
}

}  // namespace
}  // namespace uw::sim
