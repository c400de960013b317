#include "calib/laser_line_fit.h"

#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "calib/board.h"
#include "calib/board_pose.h"
#include "calib/mission_scene_testing.h"
#include "common/util/error.h"
#include "common/util/random.h"
#include "sim/laser.h"

namespace uw {
namespace {

using testing_mission::AngleDeg;
using testing_mission::SurveyCamera;

constexpr double kDegree = M_PI / 180.0;

// The board's pose from its corners with 0.3 px noise, as a calibration
// session would have it.
Rigid3d BoardPoseFromNoisyCorners(const Camera& camera,
                                  const CalibrationBoard& board,
                                  const Rigid3d& cam_from_board,
                                  double sigma_px, SplitMix64Stream* noise) {
  BoardObservation corners;
  for (const Eigen::Vector3d& corner : board.CornersInBoard()) {
    // mrcal's pixel convention, as the detectors give corners.
    corners.pixels.push_back(camera.ImgFromCam(cam_from_board * corner) -
                             Eigen::Vector2d(0.5, 0.5) +
                             sigma_px * noise->GaussianPair());
    corners.weights.push_back(1.0);
  }
  return *EstimateBoardPose(camera, board, corners);
}

struct Session {
  std::vector<std::vector<LaserBoardSpot>> spots;  // per laser
};

// A 9x7 board (8 cm squares) at `num_distances` distances from 0.6 to 3.6 m,
// tilted up to 10 deg; each laser's spot where its beam meets the board,
// projected, with spot_sigma_px noise.
Session BoardSession(const Camera& camera, const LaserSetup& setup,
                     int num_distances, double spot_sigma_px, uint64_t seed) {
  const CalibrationBoard board = ParseBoard("chessboard:9x7:0.08");
  SplitMix64Stream random(seed);
  Session session;
  session.spots.resize(setup.lasers.size());
  for (int i = 0; i < num_distances; ++i) {
    const double distance = 0.6 + 3.0 * i / (num_distances - 1);
    Rigid3d cam_from_board;
    cam_from_board.rotation =
        Eigen::Quaterniond(Eigen::AngleAxisd(random.Uniform(-10, 10) * kDegree,
                                             Eigen::Vector3d::UnitX()) *
                           Eigen::AngleAxisd(random.Uniform(-10, 10) * kDegree,
                                             Eigen::Vector3d::UnitY()));
    cam_from_board.translation =
        Eigen::Vector3d(0, 0, distance) -
        cam_from_board.rotation * Eigen::Vector3d(0.32, 0.24, 0.0);
    const Rigid3d estimate =
        BoardPoseFromNoisyCorners(camera, board, cam_from_board, 0.3, &random);
    const Eigen::Vector3d normal = cam_from_board.RotationMatrix().col(2);
    for (size_t l = 0; l < setup.lasers.size(); ++l) {
      const Laser& laser = setup.lasers[l];
      const double t =
          normal.dot(cam_from_board.translation - laser.origin_in_cam) /
          normal.dot(laser.direction_in_cam);
      const Eigen::Vector3d hit =
          laser.origin_in_cam + t * laser.direction_in_cam;
      session.spots[l].push_back(
          {"board" + std::to_string(i), estimate,
           camera.ImgFromCam(hit) + spot_sigma_px * random.GaussianPair()});
    }
  }
  return session;
}

// Acceptance: 0.3 px spot noise (and 0.3 px corner noise), >= 8 distances:
// direction within 0.05 deg, origin within 1 mm, for set-up C's 4 lasers.
TEST(FitLaserLine, RecoversSetupCFromNoisyBoardSpots) {
  const Camera camera = SurveyCamera();
  const LaserSetup truth = sim::TrueLaserSetup(sim::LaserOptions());
  const Session session = BoardSession(camera, truth, 12, 0.3, 21);
  for (size_t l = 0; l < truth.lasers.size(); ++l) {
    const Laser& laser = truth.lasers[l];
    const LaserLineFit fit = FitLaserLine(laser.name, camera, session.spots[l],
                                          LaserLineFitOptions());
    const double angle =
        AngleDeg(fit.laser.direction_in_cam, laser.direction_in_cam);
    const double origin_mm =
        1000.0 * (fit.laser.origin_in_cam - laser.origin_in_cam).norm();
    const double sigma_deg =
        std::sqrt(fit.laser.direction_cov.trace()) / kDegree;
    const double sigma_mm = 1000.0 * std::sqrt(fit.laser.origin_cov.trace());
    std::printf(
        "[ figures ] laser %s: direction %.4f deg off (fit sigma "
        "%.4f), origin %.3f mm off (fit sigma %.3f); line RMS %.2f "
        "mm\n",
        laser.name.c_str(), angle, sigma_deg, origin_mm, sigma_mm,
        1000.0 * fit.rms_distance_m);
    EXPECT_LT(angle, 0.05) << laser.name;
    EXPECT_LT(origin_mm, 1.0) << laser.name;
    EXPECT_EQ(std::count(fit.inliers.begin(), fit.inliers.end(), true), 12);
    LaserSetup fitted;
    fitted.name = "fitted";
    fitted.lasers = {fit.laser};
    EXPECT_NO_THROW(fitted.Check());
  }
}

TEST(FitLaserLine, SetsABadSpotAsideAndRefusesTooLittleDepth) {
  const Camera camera = SurveyCamera();
  const LaserSetup truth = sim::TrueLaserSetup(sim::LaserOptions());
  Session session = BoardSession(camera, truth, 10, 0.3, 4);
  std::vector<LaserBoardSpot> spots = session.spots[0];
  spots[4].pixel += Eigen::Vector2d(40.0, -25.0);  // another blob
  const LaserLineFit fit =
      FitLaserLine("L1", camera, spots, LaserLineFitOptions());
  EXPECT_FALSE(fit.inliers[4]);
  EXPECT_LT(
      AngleDeg(fit.laser.direction_in_cam, truth.lasers[0].direction_in_cam),
      0.05);
  // Three boards at about the same distance cannot give a direction.
  const std::vector<LaserBoardSpot> close(spots.begin(), spots.begin() + 2);
  EXPECT_THROW(FitLaserLine("L1", camera, close, LaserLineFitOptions()), Error);
  std::vector<LaserBoardSpot> same_depth = {spots[0], spots[0], spots[0]};
  try {
    FitLaserLine("L1", camera, same_depth, LaserLineFitOptions());
    ADD_FAILURE() << "fitted a line at one depth";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("laser L1: the spots do not"),
              std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace uw
