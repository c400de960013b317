#include "laserscale/laser_setup.h"

#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "common/util/error.h"

namespace uw {
namespace {

LaserSetup TwoLasers() {
  LaserSetup setup;
  setup.name = "C";
  setup.dives = {1, 3};
  Laser left;
  left.name = "L0";
  left.origin_in_cam = {-0.165, 0.01, 0.0};
  left.direction_in_cam = Eigen::Vector3d(0.01, -0.003, 1.0).normalized();
  left.origin_cov = 1e-6 * Eigen::Matrix3d::Identity();
  left.origin_cov(2, 2) = 0.0;
  left.direction_cov =
      IsotropicDirectionCovariance(left.direction_in_cam, 0.002);
  Laser right = left;
  right.name = "L1";
  right.origin_in_cam.x() = 0.165;
  right.colour = {0.0, 1.0, 0.2};
  setup.lasers = {left, right};
  return setup;
}

std::string ReplaceFirst(std::string text, const std::string& from,
                         const std::string& to) {
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

TEST(LaserSetup, JsonRoundTripKeepsEveryBit) {
  const LaserSetup setup = TwoLasers();
  const std::vector<LaserSetup> read =
      ParseLasersJson(LasersJsonText({setup}), "test");
  ASSERT_EQ(read.size(), 1u);
  EXPECT_EQ(read[0].name, "C");
  EXPECT_EQ(read[0].dives, setup.dives);
  ASSERT_EQ(read[0].lasers.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    const Laser& a = setup.lasers[i];
    const Laser& b = read[0].lasers[i];
    EXPECT_EQ(a.name, b.name);
    // nlohmann writes doubles with enough digits to read them back exactly.
    EXPECT_EQ(a.origin_in_cam, b.origin_in_cam);
    EXPECT_EQ(a.direction_in_cam, b.direction_in_cam);
    EXPECT_EQ(a.origin_cov, b.origin_cov);
    EXPECT_EQ(a.direction_cov, b.direction_cov);
    EXPECT_EQ(a.colour, b.colour);
  }
}

TEST(LaserSetup, IsotropicDirectionCovarianceIsRankTwoAcrossTheBeam) {
  const Eigen::Vector3d direction = Eigen::Vector3d(0.2, -0.1, 1.0);
  const Eigen::Matrix3d cov = IsotropicDirectionCovariance(direction, 0.01);
  EXPECT_NEAR((cov * direction.normalized()).norm(), 0.0, 1e-18);
  const Eigen::Vector3d across =
      direction.cross(Eigen::Vector3d::UnitX()).normalized();
  EXPECT_NEAR(across.dot(cov * across), 1e-4, 1e-18);
}

TEST(LaserSetup, RejectsBadGeometryNamingTheLaser) {
  const auto expect_error = [](LaserSetup setup, const std::string& part) {
    try {
      setup.Check();
      ADD_FAILURE() << "no error, expected " << part;
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what()).find(part), std::string::npos)
          << error.what();
    }
  };
  LaserSetup off_plane = TwoLasers();
  off_plane.lasers[1].origin_in_cam.z() = 0.01;
  expect_error(off_plane, "laser L1: origin_in_cam");
  LaserSetup not_unit = TwoLasers();
  not_unit.lasers[0].direction_in_cam *= 1.001;
  expect_error(not_unit, "laser L0: direction_in_cam");
  LaserSetup backward = TwoLasers();
  backward.lasers[0].direction_in_cam = -Eigen::Vector3d::UnitZ();
  expect_error(backward, "z > 0");
  LaserSetup negative = TwoLasers();
  negative.lasers[0].origin_cov(0, 0) = -1e-6;
  expect_error(negative, "origin_cov: not positive semi-definite");
  LaserSetup asymmetric = TwoLasers();
  asymmetric.lasers[1].direction_cov(0, 1) += 1e-6;
  expect_error(asymmetric, "direction_cov: not symmetric");
  LaserSetup twice = TwoLasers();
  twice.lasers[1].name = "L0";
  expect_error(twice, "name used twice");
  LaserSetup colour = TwoLasers();
  colour.lasers[0].colour.x() = 1.5;
  expect_error(colour, "colour");
  LaserSetup black = TwoLasers();
  black.lasers[1].colour.setZero();
  expect_error(black, "laser L1: colour is black");
  LaserSetup empty = TwoLasers();
  empty.lasers.clear();
  expect_error(empty, "no lasers");
}

TEST(LaserSetup, ParseRejectsMalformedFilesNamingFileAndKey) {
  const std::string good = LasersJsonText({TwoLasers()});
  const auto expect_error = [](const std::string& text,
                               const std::string& part) {
    try {
      ParseLasersJson(text, "cal/lasers.json");
      ADD_FAILURE() << "no error, expected " << part;
    } catch (const Error& error) {
      const std::string message = error.what();
      EXPECT_NE(message.find("cal/lasers.json"), std::string::npos) << message;
      EXPECT_NE(message.find(part), std::string::npos) << message;
    }
  };
  expect_error("{", "parse error");
  expect_error(ReplaceFirst(good, "\"uwmetric-lasers\"", "\"other\""),
               "expected format");
  expect_error(ReplaceFirst(good, "\"colour\"", "\"color\""),
               "lasers[0]: unknown key \"color\"");
  expect_error(ReplaceFirst(good, "\"direction_in_cam\"", "\"direction\""),
               "missing key \"direction_in_cam\"");
  nlohmann::json json = nlohmann::json::parse(good);
  json["setups"][0]["lasers"][1]["origin_in_cam"] = {0.1, 0.0};
  expect_error(json.dump(), "origin_in_cam: expected an array of 3 numbers");
  json = nlohmann::json::parse(good);
  json["setups"][0]["lasers"][0]["origin_in_cam"][2] = 0.05;
  expect_error(json.dump(), "laser L0: origin_in_cam must be finite with z");
  json = nlohmann::json::parse(good);
  json["setups"].push_back(json["setups"][0]);
  expect_error(json.dump(), "set-up name \"C\" used twice");
  expect_error(R"({"format": "uwmetric-lasers", "version": 1, "setups": []})",
               "non-empty array");
}

}  // namespace
}  // namespace uw
