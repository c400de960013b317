#include "calib/laser_mission_calibration.h"

#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "calib/mission_scene_testing.h"
#include "calib/same_model_check.h"
#include "common/util/error.h"
#include "sim/laser.h"

namespace uw {
namespace {

using testing_mission::AngleDeg;
using testing_mission::Floor;
using testing_mission::Localized;
using testing_mission::MakeMission;
using testing_mission::Mission;

constexpr double kDegree = M_PI / 180.0;

// The same spots in a model of scale k: positions scaled, pixels unchanged.
std::vector<MissionSpot> Scaled(std::vector<MissionSpot> spots, double k) {
  for (MissionSpot& spot : spots) spot.cam_from_world.translation *= k;
  return spots;
}

// The origins are known; the directions start 0.4 deg off (a re-mounting).
LaserSetup APriori(const LaserSetup& truth) {
  LaserSetup a_priori = truth;
  for (Laser& laser : a_priori.lasers) {
    laser.direction_in_cam =
        (Eigen::AngleAxisd(0.4 * kDegree, Eigen::Vector3d::UnitX()) *
         laser.direction_in_cam)
            .normalized();
  }
  return a_priori;
}

// Acceptance (issue 6, 5): directions from models of scale 0.237 and 1.0
// agree within their sigma; and they are the true ones within 3 sigma, the
// image-line RMS at the spots' noise level in each dive.
TEST(CalibrateLaserFromMission, DirectionsDoNotDependOnTheModelsScale) {
  const LaserSetup truth = sim::TrueLaserSetup(sim::LaserOptions());
  const LaserSetup a_priori = APriori(truth);
  const RayCaster metric(Floor(1.0));
  const RayCaster small(Floor(0.237));
  const Mission mission = MakeMission(metric, truth, 40, 0.3, 7);
  MissionCalibrationOptions options;
  for (size_t l = 0; l < truth.lasers.size(); ++l) {
    const Laser& laser = truth.lasers[l];
    const MissionLaserCalibration one = CalibrateLaserFromMission(
        a_priori.lasers[l], metric, mission.spots[l], options);
    const MissionLaserCalibration other = CalibrateLaserFromMission(
        a_priori.lasers[l], small, Scaled(mission.spots[l], 0.237), options);
    const double between =
        AngleDeg(one.laser.direction_in_cam, other.laser.direction_in_cam);
    const double error =
        AngleDeg(one.laser.direction_in_cam, laser.direction_in_cam);
    std::printf(
        "[ figures ] laser %s: %d of %zu spots, depths %.2f-%.2f m; "
        "direction %.4f deg off the truth (MC sigma %.4f deg, %d "
        "iterations), scale 1 vs 0.237: %.2e deg (sigma %.4f); a-priori "
        "%.3f deg off; image-line RMS %.3f px (dive 1 %.3f, dive 2 %.3f)\n",
        laser.name.c_str(), one.num_inliers, mission.spots[l].size(),
        one.min_depth, one.max_depth, error, one.sigma_deg,
        one.num_iterations_used, between, other.sigma_deg,
        one.angle_from_a_priori_deg, one.rms_px, one.rms_by_dive[0].rms_px,
        one.rms_by_dive[1].rms_px);
    EXPECT_LT(between, std::min(one.sigma_deg, other.sigma_deg)) << laser.name;
    EXPECT_NEAR(one.sigma_deg, other.sigma_deg, 0.1 * one.sigma_deg);
    EXPECT_LT(error, 3.0 * one.sigma_deg) << laser.name;
    EXPECT_LT(error, 0.1) << laser.name;
    EXPECT_GT(one.sigma_deg, 0.0);
    EXPECT_EQ(one.num_iterations_used, options.num_iterations);
    // The origin is the a-priori one; the beam's image goes through the
    // spots to their noise, 0.3 px per axis: over 20 spots a dive's RMS
    // has a spread of 0.3 / sqrt(40) = 0.047 px, over all 40 of 0.034 px,
    // and the fit's own error adds (0.014 deg moves the line 0.2 px).
    EXPECT_EQ(one.laser.origin_in_cam, a_priori.lasers[l].origin_in_cam);
    EXPECT_GT(one.rms_px, 0.2) << laser.name;
    EXPECT_LT(one.rms_px, 0.45) << laser.name;
    ASSERT_EQ(one.rms_by_dive.size(), 2u);
    for (const auto& dive : one.rms_by_dive) {
      EXPECT_GT(dive.rms_px, 0.15) << laser.name << " dive " << dive.dive;
      EXPECT_LT(dive.rms_px, 0.5) << laser.name << " dive " << dive.dive;
    }
    EXPECT_NEAR(one.rms_px, other.rms_px, 1e-6);
    LaserSetup fitted;
    fitted.name = "fitted";
    fitted.lasers = {one.laser};
    EXPECT_NO_THROW(fitted.Check());
  }
}

// The Monte Carlo's sigma is the spread of the direction: over 25
// independent missions (4 lasers each) the mean of error^2 / trace(cov)
// is 1 (a 2-dof error; its spread over 100 draws is about 0.1).
TEST(CalibrateLaserFromMission, MonteCarloSigmaMatchesTheSpread) {
  const LaserSetup truth = sim::TrueLaserSetup(sim::LaserOptions());
  const RayCaster floor(Floor(1.0));
  MissionCalibrationOptions options;
  options.num_iterations = 500;
  double sum = 0.0;
  int count = 0;
  for (uint64_t seed = 100; seed < 125; ++seed) {
    const Mission mission = MakeMission(floor, truth, 40, 0.3, seed);
    for (size_t l = 0; l < truth.lasers.size(); ++l) {
      const MissionLaserCalibration fit = CalibrateLaserFromMission(
          truth.lasers[l], floor, mission.spots[l], options);
      const double error = AngleDeg(fit.laser.direction_in_cam,
                                    truth.lasers[l].direction_in_cam);
      sum += error * error / (fit.sigma_deg * fit.sigma_deg);
      ++count;
    }
  }
  std::printf("[ figures ] mean error^2 / sigma^2 over %d fits: %.3f\n", count,
              sum / count);
  EXPECT_GT(sum / count, 0.7);
  EXPECT_LT(sum / count, 1.3);
}

// Spots over a narrow range of distances give a direction with a lever arm
// too short: its Monte Carlo sigma says so (ch4 spec §14.4).
TEST(CalibrateLaserFromMission, NarrowDistancesInflateTheSigma) {
  const LaserSetup truth = sim::TrueLaserSetup(sim::LaserOptions());
  const RayCaster floor(Floor(1.0));
  const Mission wide = MakeMission(floor, truth, 40, 0.3, 9, 4.5);
  const Mission narrow = MakeMission(floor, truth, 40, 0.3, 9, 2.5);
  MissionCalibrationOptions options;
  options.num_iterations = 500;
  for (size_t l = 0; l < truth.lasers.size(); ++l) {
    const double wide_sigma = CalibrateLaserFromMission(truth.lasers[l], floor,
                                                        wide.spots[l], options)
                                  .sigma_deg;
    const double narrow_sigma =
        CalibrateLaserFromMission(truth.lasers[l], floor, narrow.spots[l],
                                  options)
            .sigma_deg;
    std::printf(
        "[ figures ] laser %s: sigma %.4f deg from 1.5-4.5 m, %.4f deg from "
        "1.5-2.5 m\n",
        truth.lasers[l].name.c_str(), wide_sigma, narrow_sigma);
    EXPECT_GT(narrow_sigma, 1.5 * wide_sigma) << truth.lasers[l].name;
  }
}

// Same seed, same answer, whatever the threads; a bad spot is set aside.
TEST(CalibrateLaserFromMission, DeterministicAndRobust) {
  const LaserSetup truth = sim::TrueLaserSetup(sim::LaserOptions());
  const RayCaster floor(Floor(1.0));
  Mission mission = MakeMission(floor, truth, 30, 0.3, 11);
  std::vector<MissionSpot>& spots = mission.spots[0];
  spots[5].pixel += Eigen::Vector2d(35.0, -20.0);  // a reflection
  MissionCalibrationOptions options;
  options.num_iterations = 200;
  options.num_threads = 1;
  const MissionLaserCalibration serial =
      CalibrateLaserFromMission(truth.lasers[0], floor, spots, options);
  options.num_threads = 2;
  const MissionLaserCalibration parallel =
      CalibrateLaserFromMission(truth.lasers[0], floor, spots, options);
  EXPECT_EQ(serial.laser.direction_cov, parallel.laser.direction_cov);
  EXPECT_FALSE(serial.inliers[5]);
  EXPECT_EQ(serial.problems[5], "off the line fitted to the other spots");
  EXPECT_LT(
      AngleDeg(serial.laser.direction_in_cam, truth.lasers[0].direction_in_cam),
      0.1);
}

TEST(CalibrateLaserFromMission, RefusesTooFewSpotsAndTooLittleDepth) {
  const LaserSetup truth = sim::TrueLaserSetup(sim::LaserOptions());
  const RayCaster floor(Floor(1.0));
  const Mission mission = MakeMission(floor, truth, 30, 0.3, 3);
  const std::vector<MissionSpot>& spots = mission.spots[1];
  const std::vector<MissionSpot> few(spots.begin(), spots.begin() + 4);
  EXPECT_THROW(CalibrateLaserFromMission(truth.lasers[1], floor, few,
                                         MissionCalibrationOptions()),
               Error);
  // Ten images from 1.5 to 2.4 m above the floor do not span the depth
  // ratio of 2 asked for here.
  const std::vector<MissionSpot> shallow(spots.begin(), spots.begin() + 10);
  MissionCalibrationOptions options;
  options.min_depth_ratio = 2.0;
  try {
    CalibrateLaserFromMission(truth.lasers[1], floor, shallow, options);
    ADD_FAILURE() << "fitted a direction over too little depth";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("laser L1: "), std::string::npos)
        << error.what();
    EXPECT_NE(std::string(error.what()).find("times as deep"),
              std::string::npos)
        << error.what();
  }
}

// Acceptance (issue 6, 5): points from two different models are refused,
// whether the poses or the mesh come from the other model.
TEST(SameModelCheck, RefusesPosesAndMeshesOfAnotherModel) {
  const LaserSetup truth = sim::TrueLaserSetup(sim::LaserOptions());
  const RayCaster metric(Floor(1.0));
  const RayCaster small(Floor(0.237));
  const Mission mission = MakeMission(metric, truth, 10, 0.3, 5);
  const std::vector<LocalizedImage> in_metric = Localized(metric, mission, 1.0);
  const std::vector<LocalizedImage> in_small = Localized(small, mission, 0.237);
  std::vector<Eigen::Vector3d> metric_points;
  for (const LocalizedImage& image : in_metric) {
    for (const auto& inlier : image.inliers) {
      metric_points.push_back(inlier.point_in_world);
    }
  }
  EXPECT_NO_THROW(CheckPosesUseModelPoints(metric_points, in_metric,
                                           "poses.json", "sparse/0"));
  try {
    CheckPosesUseModelPoints(metric_points, in_small, "poses.json", "sparse/0");
    ADD_FAILURE() << "accepted poses of another model";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("poses.json: image L0.png: "),
              std::string::npos)
        << error.what();
  }
  EXPECT_NO_THROW(CheckMeshFitsPoses(metric, in_metric, "mesh.ply"));
  EXPECT_NO_THROW(CheckMeshFitsPoses(small, in_small, "mesh.ply"));
  try {
    CheckMeshFitsPoses(small, in_metric, "mesh.ply");
    ADD_FAILURE() << "accepted the mesh of another model";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("mesh.ply: "), std::string::npos)
        << error.what();
  }
  EXPECT_THROW(CheckMeshFitsPoses(metric, in_small, "mesh.ply"), Error);
}

}  // namespace
}  // namespace uw
