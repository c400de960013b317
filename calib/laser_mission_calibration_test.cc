#include "calib/laser_mission_calibration.h"

#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "calib/same_model_check.h"
#include "colmap_plugins/util/error.h"
#include "colmap_plugins/util/random.h"
#include "sim/laser.h"

namespace uw {
namespace {

constexpr double kDegree = M_PI / 180.0;

Camera SurveyCamera() {
  Camera camera;
  camera.model_id = CameraModelId::kSimpleRadial;
  camera.width = 1024;
  camera.height = 768;
  camera.params = {850.0, 512.0, 384.0, -0.04};
  return camera;
}

// A rough sea floor (metres, z up): 0.3 m swells and 0.1 m ripples, faces
// counter-clockwise seen from above (the water).
TriangleMesh Floor(double scale) {
  TriangleMesh mesh;
  const int n = 57;  // 14 m in 0.25 m steps
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const double x = -2.0 + 0.25 * i;
      const double y = -2.0 + 0.25 * j;
      const double z = 0.3 * std::sin(0.7 * x) * std::cos(0.5 * y) +
                       0.1 * std::sin(1.9 * x + 2.3 * y);
      mesh.vertices.push_back(scale * Eigen::Vector3d(x, y, z));
    }
  }
  for (int j = 0; j + 1 < n; ++j) {
    for (int i = 0; i + 1 < n; ++i) {
      const int a = j * n + i;
      mesh.triangles.emplace_back(a, a + 1, a + n + 1);
      mesh.triangles.emplace_back(a, a + n + 1, a + n);
    }
  }
  return mesh;
}

struct Mission {
  std::vector<Rigid3d> cam_from_world;          // metres
  std::vector<std::vector<MissionSpot>> spots;  // per laser, model scale 1
};

// `num_images` downward views from 1.5 to 4.5 m above the floor, tilted up
// to 8 deg; each laser's spot where its true beam meets the floor, with
// sigma_px noise (and that covariance). The first half is dive 1, the rest
// dive 2.
Mission MakeMission(const RayCaster& floor, const LaserSetup& truth,
                    int num_images, double sigma_px, uint64_t seed) {
  const Camera camera = SurveyCamera();
  SplitMix64Stream random(seed);
  Mission mission;
  mission.spots.resize(truth.lasers.size());
  const Eigen::Matrix3d down =
      (Eigen::Matrix3d() << 1, 0, 0, 0, -1, 0, 0, 0, -1).finished();
  for (int i = 0; i < num_images; ++i) {
    const Eigen::Matrix3d tilt =
        (Eigen::AngleAxisd(random.Uniform(-8, 8) * kDegree,
                           Eigen::Vector3d::UnitX()) *
         Eigen::AngleAxisd(random.Uniform(-8, 8) * kDegree,
                           Eigen::Vector3d::UnitY()))
            .toRotationMatrix();
    const Eigen::Matrix3d world_from_cam = (tilt * down).transpose();
    const Eigen::Vector3d centre(random.Uniform(1, 9), random.Uniform(1, 9),
                                 1.5 + 3.0 * i / (num_images - 1));
    Rigid3d cam_from_world;
    cam_from_world.rotation = Eigen::Quaterniond(world_from_cam.transpose());
    cam_from_world.translation = -(world_from_cam.transpose() * centre);
    mission.cam_from_world.push_back(cam_from_world);
    for (size_t l = 0; l < truth.lasers.size(); ++l) {
      const Laser& laser = truth.lasers[l];
      const auto hit =
          floor.Intersect(centre + world_from_cam * laser.origin_in_cam,
                          world_from_cam * laser.direction_in_cam);
      if (!hit) continue;
      MissionSpot spot;
      spot.image = "L" + std::to_string(i) + ".png";
      spot.dive = i < num_images / 2 ? 1 : 2;
      spot.camera = camera;
      spot.cam_from_world = cam_from_world;
      spot.pixel = camera.ImgFromCam(cam_from_world * hit->point_in_world) +
                   sigma_px * random.GaussianPair();
      spot.covariance_px = sigma_px * sigma_px * Eigen::Matrix2d::Identity();
      mission.spots[l].push_back(spot);
    }
  }
  return mission;
}

// The same spots in a model of scale k: positions scaled, pixels unchanged.
std::vector<MissionSpot> Scaled(std::vector<MissionSpot> spots, double k) {
  for (MissionSpot& spot : spots) spot.cam_from_world.translation *= k;
  return spots;
}

double AngleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) / kDegree;
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
  std::printf("[ figures ] mean error^2 / sigma^2 over %d fits: %.3f\n",
              count, sum / count);
  EXPECT_GT(sum / count, 0.7);
  EXPECT_LT(sum / count, 1.3);
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

// Localized images whose inliers are floor points seen by the camera.
std::vector<LocalizedImage> Localized(const RayCaster& floor,
                                      const Mission& mission, double k) {
  const Camera camera = SurveyCamera();
  std::vector<LocalizedImage> images;
  for (size_t i = 0; i < mission.cam_from_world.size(); ++i) {
    LocalizedImage image;
    image.name = "L" + std::to_string(i) + ".png";
    image.success = true;
    image.camera = camera;
    image.cam_from_world = mission.cam_from_world[i];
    image.cam_from_world.translation *= k;
    const Rigid3d world_from_cam = image.cam_from_world.Inverse();
    for (int v = 50; v < 768; v += 150) {
      for (int u = 50; u < 1024; u += 150) {
        const Eigen::Vector3d ray =
            world_from_cam.RotationMatrix() *
            CameraModelCamFromImg(camera.model_id, camera.params.data(),
                                  Eigen::Vector2d(u, v))
                .normalized();
        const auto hit = floor.Intersect(world_from_cam.translation, ray);
        if (hit) {
          image.inliers.push_back({Eigen::Vector2d(u, v), hit->point_in_world});
        }
      }
    }
    images.push_back(image);
  }
  return images;
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
