#include "sim/laser.h"

#include <cmath>

#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "common/mesh/test_meshes.h"
#include "common/util/error.h"

namespace uw::sim {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

LaserOptions Preset(const std::string& name) {
  LaserOptions options;
  options.setup = name;
  return options;
}

double AngleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * kRadToDeg;
}

Camera Pinhole() {
  Camera camera;
  camera.camera_id = 1;
  camera.model_id = CameraModelId::kPinhole;
  camera.width = 640;
  camera.height = 480;
  camera.params = {500.0, 500.0, 320.0, 240.0};
  return camera;
}

// The plane z = distance facing a camera at the origin, 20 m wide.
TriangleMesh FacingPlane(double distance) {
  TriangleMesh mesh;
  AddGrid({-10, -10, distance}, {0, 20, 0}, {20, 0, 0}, 2, 2, &mesh);
  return mesh;
}

TEST(LaserPresets, MatchTheThesisConfigurations) {
  const LaserSetup a = TrueLaserSetup(Preset("A"));
  ASSERT_EQ(a.lasers.size(), 4u);
  for (const Laser& laser : a.lasers) {
    EXPECT_EQ(laser.direction_in_cam, Eigen::Vector3d::UnitZ());
    EXPECT_NEAR(laser.origin_in_cam.head<2>().norm(), 0.1 * std::sqrt(2.0),
                1e-15);
  }
  const LaserSetup b = TrueLaserSetup(Preset("B"));
  ASSERT_EQ(b.lasers.size(), 4u);
  for (int pair = 0; pair < 2; ++pair) {
    const Laser& first = b.lasers[2 * pair];
    const Laser& second = b.lasers[2 * pair + 1];
    // Parallel, off the axis, equidistant from the centre on opposite sides.
    EXPECT_EQ(first.direction_in_cam, b.lasers[0].direction_in_cam);
    EXPECT_EQ(second.direction_in_cam, b.lasers[0].direction_in_cam);
    EXPECT_GT(AngleDeg(first.direction_in_cam, Eigen::Vector3d::UnitZ()), 3.0);
    EXPECT_NEAR(first.origin_in_cam.norm(), 0.15, 1e-15);
    EXPECT_NEAR((first.origin_in_cam + second.origin_in_cam).norm(), 0.0,
                1e-15);
  }
  const LaserSetup c = TrueLaserSetup(Preset("C"));
  ASSERT_EQ(c.lasers.size(), 4u);
  for (size_t i = 0; i < c.lasers.size(); ++i) {
    const Laser& laser = c.lasers[i];
    EXPECT_NEAR(laser.origin_in_cam.head<2>().norm(), 0.165, 0.0025);
    const double misalignment =
        AngleDeg(laser.direction_in_cam, Eigen::Vector3d::UnitZ());
    EXPECT_GT(misalignment, 0.3);
    EXPECT_LT(misalignment, 1.1);
    for (size_t j = 0; j < i; ++j) {
      EXPECT_GT(AngleDeg(laser.direction_in_cam, c.lasers[j].direction_in_cam),
                0.3);
    }
  }
  for (const LaserSetup* setup : {&a, &b, &c}) EXPECT_NO_THROW(setup->Check());
}

TEST(LaserOptions, JsonRoundTripAndErrors) {
  LaserOptions options = Preset("custom");
  Laser laser;
  laser.name = "green";
  laser.origin_in_cam = {0.2, 0.0, 0.0};
  laser.direction_in_cam = Eigen::Vector3d(-0.05, 0.0, 1.0).normalized();
  laser.colour = {0.0, 1.0, 0.0};
  options.custom_lasers = {laser};
  options.optics.divergence_mrad = 0.5;
  options.every_nth_image = 1;
  options.auxiliary = "absent";
  nlohmann::json json = options;
  LaserOptions read;
  json.get_to(read);
  EXPECT_EQ(nlohmann::json(read), json);
  EXPECT_NO_THROW(read.Check());
  ASSERT_EQ(read.custom_lasers.size(), 1u);
  EXPECT_EQ(read.custom_lasers[0].direction_in_cam, laser.direction_in_cam);

  const auto expect_error = [](const nlohmann::json& bad,
                               const std::string& part) {
    try {
      LaserOptions parsed;
      bad.get_to(parsed);
      parsed.Check();
      ADD_FAILURE() << "no error, expected " << part;
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what()).find(part), std::string::npos)
          << error.what();
    }
  };
  expect_error({{"setup", "D"}}, "lasers.setup = \"D\"");
  expect_error({{"auxiliary", "gone"}}, "lasers.auxiliary");
  expect_error({{"optics", {{"waist", 1}}}}, "lasers.optics: unknown key");
  expect_error({{"optics", {{"waist_radius_m", 0.0}}}}, "waist_radius_m");
  expect_error({{"every_nth_image", -1}}, "every_nth_image");
  expect_error({{"aux_gain", 0.0}}, "aux_gain");
  expect_error({{"setup", "custom"}}, "needs lasers.custom_lasers");
  json["custom_lasers"][0]["origin_in_cam"][2] = 0.1;
  expect_error(json, "origin_in_cam must be finite with z = 0");
}

TEST(CalibratedLaserSetup, ErrorsHaveTheStatedSigmasAndCovariances) {
  LaserOptions options = Preset("C");
  options.calibration_origin_sigma_m = 0.002;
  options.calibration_direction_sigma_deg = 0.1;
  const LaserSetup truth = TrueLaserSetup(options);
  EXPECT_EQ(LasersJsonText({CalibratedLaserSetup(truth, options, 7)}),
            LasersJsonText({CalibratedLaserSetup(truth, options, 7)}));
  double origin_sq = 0.0, angle_sq = 0.0;
  int count = 0;
  for (uint64_t seed = 0; seed < 2000; ++seed) {
    const LaserSetup calibrated = CalibratedLaserSetup(truth, options, seed);
    for (size_t i = 0; i < truth.lasers.size(); ++i) {
      const Laser& t = truth.lasers[i];
      const Laser& c = calibrated.lasers[i];
      EXPECT_EQ(c.origin_in_cam.z(), 0.0);
      origin_sq += (c.origin_in_cam - t.origin_in_cam).squaredNorm();
      const double angle = AngleDeg(c.direction_in_cam, t.direction_in_cam);
      angle_sq += angle * angle;
      ++count;
      EXPECT_NEAR(c.origin_cov(0, 0), 4e-6, 1e-18);
      EXPECT_NEAR(c.direction_cov.trace(), 2.0 * std::pow(0.1 / kRadToDeg, 2.0),
                  1e-15);
    }
  }
  // Two independent axes each: E|error|^2 = 2 sigma^2; 8000 draws, 3 %.
  EXPECT_NEAR(std::sqrt(origin_sq / count / 2.0), 0.002, 0.002 * 0.03);
  EXPECT_NEAR(std::sqrt(angle_sq / count / 2.0), 0.1, 0.1 * 0.03);
}

TEST(LaserBeam, ConservesPowerAndHasTheStatedRadius) {
  Laser laser;
  laser.name = "L";
  BeamOptics optics;
  optics.waist_radius_m = 0.003;
  optics.divergence_mrad = 2.0;
  optics.peak_level = 4.0;
  const LaserBeam beam(laser, optics, Rigid3d());
  double along = 0.0;
  EXPECT_DOUBLE_EQ(beam.Irradiance({0, 0, 1.0}, &along), 4.0);
  EXPECT_EQ(along, 1.0);
  const double radius_at_3m = 0.003 + 3.0 * 0.002;
  EXPECT_NEAR(beam.Irradiance({radius_at_3m, 0, 3.0}, &along) /
                  beam.Irradiance({0, 0, 3.0}, &along),
              std::exp(-2.0), 1e-12);
  EXPECT_EQ(beam.Irradiance({0, 0, -0.1}, &along), 0.0);  // behind
  // Power through a plane across the beam, at 0.5 m and 8 m.
  const auto power = [&](double t) {
    const double radius = 0.003 + t * 0.002;
    const int n = 400;
    const double step = 6.0 * radius / n;
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        double unused;
        sum += beam.Irradiance({-3.0 * radius + (i + 0.5) * step,
                                -3.0 * radius + (j + 0.5) * step, t},
                               &unused);
      }
    }
    return sum * step * step;
  };
  EXPECT_NEAR(power(8.0) / power(0.5), 1.0, 1e-6);
}

TEST(TrueLaserSpot, FirstHitOnTheAxisAndItsPixel) {
  const TriangleMesh mesh = FacingPlane(3.0);
  const RayCaster caster(mesh);
  const Camera camera = Pinhole();
  Laser laser;
  laser.name = "L";
  laser.origin_in_cam = {0.1, -0.05, 0.0};
  laser.direction_in_cam = Eigen::Vector3d(0.02, 0.01, 1.0).normalized();
  // Camera 1 m behind the world origin, rotated about its axis.
  Rigid3d cam_from_world;
  cam_from_world.rotation =
      Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
  cam_from_world.translation = {0.0, 0.0, 1.0};
  const LaserSpotTruth truth =
      TrueLaserSpot(caster, camera, cam_from_world, laser);
  ASSERT_TRUE(truth.hit);
  ASSERT_TRUE(truth.visible);
  // The plane is 4 m ahead of the camera (z = 3 in the world, camera at -1).
  const double range = 4.0 / laser.direction_in_cam.z();
  EXPECT_NEAR(truth.range_m, range, 1e-12);
  const Eigen::Vector3d expected_in_cam =
      laser.origin_in_cam + range * laser.direction_in_cam;
  EXPECT_NEAR((cam_from_world * truth.point_in_world - expected_in_cam).norm(),
              0.0, 1e-12);
  const Eigen::Vector2d pixel(320.0 + 500.0 * expected_in_cam.x() / 4.0,
                              240.0 + 500.0 * expected_in_cam.y() / 4.0);
  EXPECT_NEAR((truth.pixel - pixel).norm(), 0.0, 1e-9);
}

TEST(TrueLaserSpot, HiddenOutsideOrMissed) {
  const Camera camera = Pinhole();
  Laser laser;
  laser.name = "L";
  laser.origin_in_cam = {0.2, 0.0, 0.0};
  // A small plate between the camera and the spot, off the beam.
  TriangleMesh mesh = FacingPlane(3.0);
  AddGrid({0.05, -0.05, 1.0}, {0, 0.1, 0}, {0.1, 0, 0}, 1, 1, &mesh);
  {
    const RayCaster caster(mesh);
    const LaserSpotTruth hidden =
        TrueLaserSpot(caster, camera, Rigid3d(), laser);
    EXPECT_TRUE(hidden.hit);
    EXPECT_NEAR(hidden.range_m, 3.0, 1e-12);
    EXPECT_FALSE(hidden.visible);
  }
  {
    // A beam leaving the field of view hits the plane outside the image.
    const RayCaster caster(FacingPlane(3.0));
    laser.direction_in_cam = Eigen::Vector3d(0.7, 0.0, 1.0).normalized();
    const LaserSpotTruth outside =
        TrueLaserSpot(caster, camera, Rigid3d(), laser);
    EXPECT_TRUE(outside.hit);
    EXPECT_FALSE(outside.visible);
    // Pointing away from the plane: no hit.
    Rigid3d turned;
    turned.rotation =
        Eigen::Quaterniond(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY()));
    EXPECT_FALSE(TrueLaserSpot(caster, camera, turned, laser).hit);
  }
}

}  // namespace
}  // namespace uw::sim
