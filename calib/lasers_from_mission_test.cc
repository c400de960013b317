#include "calib/lasers_from_mission.h"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "calib/mission_scene_testing.h"
#include "sim/laser.h"

namespace uw {
namespace {

using testing_mission::AngleDeg;

// A mission's localized images and their spots, as laserscale writes them:
// one image's pose failed, one spot of laser L0 is not stable.
MissionObservations Observations(const RayCaster& floor,
                                 const testing_mission::Mission& mission,
                                 const LaserSetup& setup) {
  MissionObservations observations;
  observations.poses = testing_mission::Localized(floor, mission, 1.0);
  observations.poses[3].success = false;
  std::map<std::string, ImageSpots> by_image;
  for (size_t l = 0; l < mission.spots.size(); ++l) {
    for (const MissionSpot& m : mission.spots[l]) {
      ImageSpots& image = by_image[m.image];
      image.name = m.image;
      image.setup = setup.name;
      DetectedSpot spot;
      spot.laser = setup.lasers[l].name;
      spot.detected = true;
      spot.stable = !(l == 0 && m.image == "L5.png");
      spot.pixel = m.pixel;
      spot.covariance = m.covariance_px;
      image.spots.push_back(spot);
      observations.dives[m.image] = m.dive;
    }
  }
  for (const auto& [name, image] : by_image) {
    observations.spots.push_back(image);
  }
  return observations;
}

LaserSetup APriori(const LaserSetup& truth) {
  LaserSetup a_priori = truth;
  for (Laser& laser : a_priori.lasers) {
    laser.direction_in_cam =
        (Eigen::AngleAxisd(0.4 * M_PI / 180, Eigen::Vector3d::UnitY()) *
         laser.direction_in_cam)
            .normalized();
  }
  return a_priori;
}

TEST(GatherMissionSpots, StableSpotsOfLocalizedImagesOfTheSetup) {
  const LaserSetup truth = sim::TrueLaserSetup(sim::LaserOptions());
  const RayCaster floor(testing_mission::Floor(1.0));
  const testing_mission::Mission mission =
      testing_mission::MakeMission(floor, truth, 20, 0.3, 5);
  const MissionObservations observations = Observations(floor, mission, truth);
  const std::string l0 = truth.lasers[0].name;
  const std::vector<MissionSpot> spots =
      GatherMissionSpots(observations, truth.name, false, l0);
  // Less L3 (not localized) and L5 (not stable).
  ASSERT_EQ(spots.size(), mission.spots[0].size() - 2);
  for (const MissionSpot& spot : spots) {
    EXPECT_NE(spot.image, "L3.png");
    EXPECT_NE(spot.image, "L5.png");
    EXPECT_EQ(spot.dive, observations.dives.at(spot.image));
  }
  EXPECT_TRUE(GatherMissionSpots(observations, "other", false, l0).empty());
  EXPECT_EQ(GatherMissionSpots(observations, "other", true, l0).size(),
            spots.size());
}

TEST(CalibrateLasersFromMission, EveryLaserOfTheSetupsAndItsReport) {
  const LaserSetup truth = sim::TrueLaserSetup(sim::LaserOptions());
  const RayCaster floor(testing_mission::Floor(1.0));
  const testing_mission::Mission mission =
      testing_mission::MakeMission(floor, truth, 30, 0.3, 17);
  const LaserSetup a_priori = APriori(truth);
  MissionCalibrationOptions options;
  options.num_iterations = 50;
  std::vector<std::string> told;
  LasersFromMissionCallbacks callbacks;
  callbacks.spots_gathered = [&](const std::string& setup,
                                 const std::string& laser, size_t) {
    told.push_back("spots " + setup + " " + laser);
  };
  callbacks.laser_calibrated = [&](const std::string& setup,
                                   const MissionLaserCalibration& result,
                                   size_t num_spots) {
    told.push_back("calibrated " + setup + " " + result.laser.name);
    EXPECT_GT(result.num_inliers, 0);
    EXPECT_LE(result.num_inliers, static_cast<int>(num_spots));
  };
  const LasersFromMission result = CalibrateLasersFromMission(
      {a_priori}, floor, Observations(floor, mission, a_priori), options,
      callbacks);
  ASSERT_EQ(told.size(), 2 * truth.lasers.size());
  EXPECT_EQ(told[0], "spots " + truth.name + " " + truth.lasers[0].name);
  EXPECT_EQ(told[1], "calibrated " + truth.name + " " + truth.lasers[0].name);
  ASSERT_EQ(result.setups.size(), 1u);
  ASSERT_EQ(result.setups[0].lasers.size(), truth.lasers.size());
  EXPECT_EQ(result.report["format"], "uwmetric-lasers-from-mission");
  EXPECT_EQ(result.report["version"], 1);
  const nlohmann::json& lasers = result.report["setups"][0]["lasers"];
  ASSERT_EQ(lasers.size(), truth.lasers.size());
  for (size_t l = 0; l < truth.lasers.size(); ++l) {
    const Laser& laser = result.setups[0].lasers[l];
    EXPECT_EQ(laser.origin_in_cam, a_priori.lasers[l].origin_in_cam);
    EXPECT_LT(
        AngleDeg(laser.direction_in_cam, truth.lasers[l].direction_in_cam), 0.1)
        << laser.name;
    EXPECT_EQ(lasers[l]["monte_carlo_iterations"], 50);
    EXPECT_EQ(lasers[l]["image_line_rms_by_dive"].size(), 2u);
    EXPECT_EQ(lasers[l]["spots"].size(), lasers[l]["num_spots"]);
  }
}

TEST(DescribeMissionLaser, InliersDepthsDirectionAndTheRmsPerDive) {
  MissionLaserCalibration result;
  result.laser.name = "L1";
  result.laser.direction_in_cam = Eigen::Vector3d(0.0, 0.6, 0.8);
  result.num_inliers = 38;
  result.min_depth = 1.4213;
  result.max_depth = 4.6549;
  result.sigma_deg = 0.01416;
  result.angle_from_a_priori_deg = 0.4131;
  result.rms_px = 0.367;
  result.rms_by_dive = {{1, 20, 0.338}, {2, 18, 0.394}};
  EXPECT_EQ(DescribeMissionLaser("C", result, 40),
            "set-up C laser L1: 38 of 40 spots, depths 1.42-4.65 model units; "
            "direction (0.000000, 0.600000, 0.800000), sigma 0.0142 deg, "
            "0.413 deg from --origins'; image-line RMS 0.367 px; dive 1: "
            "0.338 px (20); dive 2: 0.394 px (18)");
}

}  // namespace
}  // namespace uw
