#include "laserscale/scale_estimators.h"

#include <cmath>
#include <iostream>
#include <limits>

#include <gtest/gtest.h>

#include "sim/laser.h"

namespace uw {
namespace {

LaserSetup ThesisSetup(const std::string& name) {
  sim::LaserOptions options;
  options.setup = name;
  return sim::TrueLaserSetup(options);
}

// Where a beam meets a surface t metres along it, in the camera frame.
Eigen::Vector3d Along(const Laser& laser, double t) {
  return laser.origin_in_cam + t * laser.direction_in_cam;
}

// A model k times too large: every camera-frame coordinate times k.
constexpr double kModelScales[] = {0.237, 1.0, 4.2};

// FUM traces the hit back along the calibrated beam, so with a true
// calibration it is exact whatever the terrain (any depth along the beam),
// the set-up (A aligned, B tilted, C misaligned) and the model's scale.
TEST(FumScale, IsExactForEverySetupDepthAndModelScale) {
  for (const char* name : {"A", "B", "C"}) {
    for (const Laser& laser : ThesisSetup(name).lasers) {
      for (const double t : {0.5, 2.0, 3.0, 4.7}) {
        for (const double k : kModelScales) {
          const ScaleEstimate estimate = FumScale(laser, k * Along(laser, t));
          ASSERT_TRUE(estimate.scale.has_value()) << estimate.problem;
          EXPECT_NEAR(*estimate.scale * k, 1.0, 1e-12)
              << name << " " << laser.name << " t " << t << " k " << k;
        }
      }
    }
  }
}

// A direction error δθ moves the traced-back origin by about t δθ, so the
// scale error grows with distance: |ε| ≈ t δθ / |O| (ch4 spec §3.2).
TEST(FumScale, DirectionErrorGrowsWithDistance) {
  const Laser truth = ThesisSetup("A").lasers[0];
  Laser calibrated = truth;
  const double error_rad = 0.05 * M_PI / 180.0;
  // Tilted away from the origin's direction: the largest effect.
  const Eigen::Vector3d away(truth.origin_in_cam.x(), truth.origin_in_cam.y(),
                             0.0);
  calibrated.direction_in_cam =
      (truth.direction_in_cam + error_rad * away.normalized()).normalized();
  double previous = 0.0;
  for (const double t : {1.0, 2.0, 4.0}) {
    const double error =
        std::abs(*FumScale(calibrated, Along(truth, t)).scale - 1.0);
    const double predicted = t * error_rad / truth.origin_in_cam.norm();
    std::cout << "[ figures ] FUM with a 0.05 deg direction error at " << t
              << " m: |scale error| " << 100 * error << " %, t dtheta / |O| "
              << 100 * predicted << " %\n";
    EXPECT_NEAR(error, predicted, 0.05 * predicted);
    EXPECT_GT(error, previous);
    previous = error;
  }
}

// PCM needs parallel beams with origins equidistant from the camera: set-up
// B's pairs are also symmetric about it, so the midpoint ray is parallel to
// the beams and PCM is exact even when the hits lie at different depths.
TEST(PcmScale, IsExactForSymmetricParallelPairsAtAnyDepths) {
  const LaserSetup b = ThesisSetup("B");
  for (const auto& [i, j] : {std::pair{0, 1}, std::pair{2, 3}}) {
    const Laser& l1 = b.lasers[i];
    const Laser& l2 = b.lasers[j];
    // The beams' perpendicular separation (B's beams are tilted, so it is
    // less than the origins' distance on Π).
    const Eigen::Vector3d across = l2.origin_in_cam - l1.origin_in_cam;
    const double separation =
        (across - across.dot(l1.direction_in_cam) * l1.direction_in_cam).norm();
    for (const auto& [t1, t2] : {std::pair{2.0, 2.0}, std::pair{2.0, 3.1}}) {
      for (const double k : kModelScales) {
        const ScaleEstimate estimate =
            PcmScale(k * Along(l1, t1), k * Along(l2, t2),
                     Eigen::Vector3d::Zero(), separation);
        ASSERT_TRUE(estimate.scale.has_value()) << estimate.problem;
        EXPECT_NEAR(*estimate.scale * k, 1.0, 1e-12);
      }
    }
  }
}

// Non-parallel beams (set-up C, each misaligned by up to 0.9 deg): PCM
// reads their divergence as scale, and more so the farther the surface.
TEST(PcmScale, NonParallelBeamsGiveADistanceDependentError) {
  const LaserSetup c = ThesisSetup("C");
  const Laser& l1 = c.lasers[0];
  const Laser& l2 = c.lasers[2];
  const double separation = (l2.origin_in_cam - l1.origin_in_cam).norm();
  double previous = 0.0;
  for (const double t : {1.0, 2.0, 4.0}) {
    const double error = std::abs(*PcmScale(Along(l1, t), Along(l2, t),
                                            Eigen::Vector3d::Zero(), separation)
                                       .scale -
                                  1.0);
    std::cout << "[ figures ] PCM on set-up C, lasers 0 and 2 at " << t
              << " m: |scale error| " << 100 * error << " %\n";
    EXPECT_GT(error, previous);
    previous = error;
  }
  EXPECT_GT(previous, 0.03);  // visibly wrong at 4 m
}

// The direct distance between two hits is right for parallel beams on a
// surface perpendicular to them, and off by the surface's tilt otherwise.
TEST(DirectScale, IsRightOnlyOnAPerpendicularSurface) {
  const LaserSetup a = ThesisSetup("A");
  const Laser& l1 = a.lasers[0];
  const Laser& l2 = a.lasers[1];
  const double separation = (l2.origin_in_cam - l1.origin_in_cam).norm();
  EXPECT_NEAR(*DirectScale(Along(l1, 3.0), Along(l2, 3.0), separation).scale,
              1.0, 1e-12);
  // A surface tilted by 30 deg along the pair: the hits are separation /
  // cos(30 deg) apart.
  const double depth_step = separation * std::tan(M_PI / 6.0);
  EXPECT_NEAR(
      *DirectScale(Along(l1, 3.0), Along(l2, 3.0 + depth_step), separation)
           .scale,
      std::cos(M_PI / 6.0), 1e-12);
}

// The four beams of set-up A hitting the plane through (0, 0, depth) with
// the given normal (camera frame): the spots (normalised image coordinates)
// and the hits of a model k times too large.
struct PlaneShot {
  std::vector<Eigen::Vector2d> spots;
  std::vector<Eigen::Vector3d> hits;
};
PlaneShot ShootPlane(const LaserSetup& setup, double depth,
                     const Eigen::Vector3d& normal, double model_scale) {
  PlaneShot shot;
  for (const Laser& laser : setup.lasers) {
    const double t =
        (Eigen::Vector3d(0, 0, depth) - laser.origin_in_cam).dot(normal) /
        laser.direction_in_cam.dot(normal);
    const Eigen::Vector3d hit = Along(laser, t);
    shot.spots.push_back(hit.head<2>() / hit.z());
    shot.hits.push_back(model_scale * hit);
  }
  return shot;
}

TEST(DavisTustingScale, IsRightOnPlanesAndWrongOnRelief) {
  const LaserSetup a = ThesisSetup("A");
  for (const double k : kModelScales) {
    const PlaneShot square_on = ShootPlane(a, 3.0, Eigen::Vector3d::UnitZ(), k);
    const ScaleEstimate estimate =
        DavisTustingScale(a.lasers, square_on.spots, square_on.hits);
    ASSERT_TRUE(estimate.scale) << estimate.problem;
    EXPECT_NEAR(*estimate.scale, 1.0 / k, 1e-12 / k);
  }
  // A tilted plane: the pairs' spacings measure the depth at their
  // midpoints only approximately, so a small error grows with the tilt, but
  // the fitted plane takes the tilt out (0.016 % at 40 deg).
  double previous_error = 0.0;
  for (const double angle_deg : {10.0, 25.0, 40.0}) {
    const double angle = angle_deg * M_PI / 180.0;
    const PlaneShot tilted = ShootPlane(
        a, 3.0, Eigen::Vector3d(std::sin(angle), 0.0, std::cos(angle)), 1.0);
    const double error = std::abs(
        *DavisTustingScale(a.lasers, tilted.spots, tilted.hits).scale - 1.0);
    EXPECT_GT(error, previous_error);
    EXPECT_LT(error, 5e-4) << angle_deg << " deg";
    previous_error = error;
  }
  // Relief: one hit 10 cm proud of the square-on plane.
  PlaneShot bumpy = ShootPlane(a, 3.0, Eigen::Vector3d::UnitZ(), 1.0);
  const double t = 2.9 / a.lasers[0].direction_in_cam.z();
  bumpy.hits[0] = Along(a.lasers[0], t);
  bumpy.spots[0] = bumpy.hits[0].head<2>() / bumpy.hits[0].z();
  EXPECT_GT(
      std::abs(*DavisTustingScale(a.lasers, bumpy.spots, bumpy.hits).scale -
               1.0),
      0.005);
}

TEST(DavisTustingScale, RefusesLasersOffTheAxis) {
  for (const std::string name : {"B", "C"}) {
    const LaserSetup setup = ThesisSetup(name);
    const PlaneShot shot =
        ShootPlane(setup, 3.0, Eigen::Vector3d::UnitZ(), 1.0);
    const ScaleEstimate estimate =
        DavisTustingScale(setup.lasers, shot.spots, shot.hits);
    EXPECT_FALSE(estimate.scale);
    EXPECT_NE(estimate.problem.find("parallel to the optical axis"),
              std::string::npos)
        << estimate.problem;
  }
  const LaserSetup a = ThesisSetup("A");
  const PlaneShot shot = ShootPlane(a, 3.0, Eigen::Vector3d::UnitZ(), 1.0);
  std::vector<Laser> three(a.lasers.begin(), a.lasers.begin() + 3);
  EXPECT_FALSE(DavisTustingScale(three, shot.spots, shot.hits).scale);
}

TEST(ScaleEstimators, ImpossibleEstimatesSayWhyAndCarryNoScale) {
  const Laser laser = ThesisSetup("A").lasers[0];
  const auto expect_problem = [](const ScaleEstimate& estimate,
                                 const std::string& words) {
    EXPECT_FALSE(estimate.scale.has_value());
    EXPECT_NE(estimate.problem.find(words), std::string::npos)
        << estimate.problem;
  };
  expect_problem(FumScale(laser, Eigen::Vector3d(0.1, 0.1, -2.0)),
                 "in front of the camera");
  expect_problem(
      FumScale(laser, Eigen::Vector3d(std::numeric_limits<double>::quiet_NaN(),
                                      0.0, 2.0)),
      "not finite");
  Laser centred = laser;
  centred.origin_in_cam.setZero();
  expect_problem(FumScale(centred, Along(laser, 2.0)), "optical centre");
  Laser sideways = laser;
  sideways.direction_in_cam = Eigen::Vector3d::UnitX();
  expect_problem(FumScale(sideways, Along(laser, 2.0)), "parallel");
  // A hit on the optical axis traced back along the axis lands on the
  // optical centre: zero displacement measured.
  expect_problem(FumScale(laser, Eigen::Vector3d(0, 0, 2)),
                 "measured through the model is 0");

  const Eigen::Vector3d hit(0.1, 0.1, 2.0);
  expect_problem(PcmScale(hit, hit, Eigen::Vector3d::Zero(), 0.2),
                 "measured through the model is 0");
  expect_problem(PcmScale(hit, 2.0 * hit, Eigen::Vector3d::Zero(), 0.0),
                 "separation must be positive");
  expect_problem(DirectScale(hit, hit, 0.2), "measured through the model is 0");
  expect_problem(DirectScale(hit, 2.0 * hit, -1.0),
                 "separation must be positive");
}

}  // namespace
}  // namespace uw
