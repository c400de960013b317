#include "sim/laser_images.h"

#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "common/util/file.h"
#include "sim/generate.h"
#include "sim/test_sim_config.h"

namespace uw::sim {
namespace {

namespace fs = std::filesystem;

Eigen::Vector3d Centre(const Rigid3d& cam_from_world) {
  return cam_from_world.Inverse().translation;
}

double AngleDeg(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return a.normalized().angularDistance(b.normalized()) * 180.0 / M_PI;
}

// Two passes of 5 stations along x, 1 m apart, looking down.
std::vector<SurveyStation> TwoPasses() {
  std::vector<SurveyStation> stations;
  for (int pass = 0; pass < 2; ++pass) {
    for (int i = 0; i < 5; ++i) {
      SurveyStation station;
      station.image_name = "0000" + std::to_string(stations.size()) + ".png";
      station.pass = pass;
      station.time_s = 2.0 * stations.size();
      station.cam_from_world.rotation = Eigen::Quaterniond(
          Eigen::AngleAxisd(0.1 * i, Eigen::Vector3d::UnitZ()));
      station.cam_from_world.translation = {-1.0 * i, -3.0 * pass, 2.5};
      stations.push_back(station);
    }
  }
  return stations;
}

TEST(PlanLaserShots, HalfwayAlongThePassWithASmallAuxiliaryMotion) {
  const std::vector<SurveyStation> stations = TwoPasses();
  LaserOptions options;
  options.every_nth_image = 2;
  const std::vector<LaserShot> shots = PlanLaserShots(stations, options, 3);
  ASSERT_EQ(shots.size(), 5u);  // after stations 1, 3, 5, 7, 9
  for (size_t k = 0; k < shots.size(); ++k) {
    const LaserShot& shot = shots[k];
    const size_t i = 2 * k + 1;
    EXPECT_EQ(shot.survey_index, i);
    EXPECT_EQ(shot.name, "L" + stations[i].image_name);
    EXPECT_EQ(shot.aux_name,
              "L" + stations[i].image_name.substr(0, 5) + "_aux.png");
    // Halfway to the next station of the pass; the last of a pass (4, 9)
    // looks back instead.
    const size_t other = (i % 5 == 4) ? i - 1 : i + 1;
    EXPECT_NEAR((Centre(shot.cam_from_world) -
                 0.5 * (Centre(stations[i].cam_from_world) +
                        Centre(stations[other].cam_from_world)))
                    .norm(),
                0.0, 1e-12);
    EXPECT_NEAR(AngleDeg(shot.cam_from_world.rotation,
                         stations[i].cam_from_world.rotation),
                0.5 * 0.1 * 180.0 / M_PI, 1e-9);
    EXPECT_DOUBLE_EQ(shot.time_s,
                     0.5 * (stations[i].time_s + stations[other].time_s));
    // The auxiliary pose: moved by exactly the configured amounts.
    EXPECT_NEAR(
        (Centre(shot.aux_cam_from_world) - Centre(shot.cam_from_world)).norm(),
        options.aux_translation_m, 1e-12);
    EXPECT_NEAR(AngleDeg(shot.aux_cam_from_world.rotation,
                         shot.cam_from_world.rotation),
                options.aux_rotation_deg, 1e-9);
  }
  // Deterministic for a seed, different for another.
  const std::vector<LaserShot> again = PlanLaserShots(stations, options, 3);
  const std::vector<LaserShot> other = PlanLaserShots(stations, options, 4);
  EXPECT_EQ(again[2].aux_cam_from_world.translation,
            shots[2].aux_cam_from_world.translation);
  EXPECT_NE(other[2].aux_cam_from_world.translation,
            shots[2].aux_cam_from_world.translation);

  options.placement = "at";
  options.every_nth_image = 1;
  const std::vector<LaserShot> at = PlanLaserShots(stations, options, 3);
  ASSERT_EQ(at.size(), stations.size());
  EXPECT_EQ(at[6].cam_from_world.translation,
            stations[6].cam_from_world.translation);
  options.every_nth_image = 0;
  EXPECT_TRUE(PlanLaserShots(stations, options, 3).empty());
}

cv::Mat Read(const fs::path& path) {
  const cv::Mat image = cv::imread(path.string(), cv::IMREAD_COLOR);
  EXPECT_FALSE(image.empty()) << path;
  return image;
}

TEST(GenerateLaserImages, WritesImagesAuxiliariesAndTruth) {
  const fs::path out = fs::temp_directory_path() /
                       ("uw_laser_images_" + std::to_string(getpid()));
  fs::remove_all(out);
  SimConfig config = SmallSimConfig();
  config.survey_options.max_images = 6;
  config.lasers.every_nth_image = 3;
  const GenerateSummary summary = Generate(config, out);
  EXPECT_EQ(summary.num_images, 6u);
  ASSERT_EQ(summary.num_laser_images, 2u);

  const std::vector<LaserSetup> calibrated =
      ReadLasersJson(out / "lasers.json");
  const std::vector<LaserSetup> truth =
      ReadLasersJson(out / "truth" / "lasers.json");
  ASSERT_EQ(calibrated.size(), 1u);
  ASSERT_EQ(truth.size(), 1u);
  EXPECT_EQ(truth[0].name, "C");
  EXPECT_EQ(truth[0].lasers[0].origin_cov, Eigen::Matrix3d::Zero());
  EXPECT_GT(calibrated[0].lasers[0].origin_cov(0, 0), 0.0);
  EXPECT_NE(calibrated[0].lasers[0].direction_in_cam,
            truth[0].lasers[0].direction_in_cam);

  const nlohmann::json images = nlohmann::json::parse(
      ReadFileToString(out / "truth" / "laser_images.json"));
  EXPECT_EQ(images.at("format"), "uwmetric-sim-laser-images");
  ASSERT_EQ(images.at("images").size(), 2u);
  int seen = 0;
  for (const nlohmann::json& shot : images.at("images")) {
    const std::string name = shot.at("name");
    const cv::Mat laser = Read(out / "laser_images" / name);
    const cv::Mat aux = Read(out / "laser_images" /
                             shot.at("aux").at("name").get<std::string>());
    EXPECT_EQ(shot.at("aux").at("lasers_on"), true);  // default "shifted"
    ASSERT_EQ(shot.at("spots").size(), 4u);
    for (const nlohmann::json& spot : shot.at("spots")) {
      if (!spot.at("visible").get<bool>()) continue;
      ++seen;
      const int col = static_cast<int>(spot.at("pixel")[0].get<double>());
      const int row = static_cast<int>(spot.at("pixel")[1].get<double>());
      // The spot is red: far more red at its centre than around it, where
      // the water has taken most of the lamp's red.
      double ring_red = 0.0;
      int ring = 0;
      for (int dr = -12; dr <= 12; ++dr) {
        for (int dc = -12; dc <= 12; ++dc) {
          const double r = std::hypot(dr, dc);
          if (r < 8.0 || r > 12.0) continue;
          ring_red += laser.at<cv::Vec3b>(row + dr, col + dc)[2];
          ++ring;
        }
      }
      EXPECT_GT(laser.at<cv::Vec3b>(row, col)[2], ring_red / ring + 40)
          << name << " " << spot.dump();
    }
  }
  EXPECT_GE(seen, 4);
  fs::remove_all(out);
}

}  // namespace
}  // namespace uw::sim
