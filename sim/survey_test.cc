#include "sim/survey.h"

#include <gtest/gtest.h>

#include "colmap_plugins/util/error.h"
#include "sim/world.h"

namespace uw::sim {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

// Only the survey frame of a world matters for planning.
World PlaneWorld(const Eigen::Vector3d& normal, const Eigen::Vector3d& along,
                 double length, double width) {
  World world;
  world.name = "plane";
  world.survey_origin = Eigen::Vector3d(5.0, -3.0, 0.5);
  world.survey_normal = normal;
  world.survey_along = along;
  world.survey_length = length;
  world.survey_width = width;
  return world;
}

Camera TestCamera() {
  Camera camera;
  camera.model_id = CameraModelId::kPinhole;
  camera.width = 1000;
  camera.height = 800;
  camera.params = {1000.0, 1000.0, 500.0, 400.0};
  return camera;
}

// Explicit overlaps and coverage, so the expected geometry does not move
// with the defaults.
SurveyOptions NoJitter() {
  SurveyOptions options;
  options.forward_overlap = 0.75;
  options.side_overlap = 0.6;
  options.coverage_along = 0.7;
  options.coverage_across = 0.7;
  options.attitude_jitter_deg = 0.0;
  options.position_jitter_m = 0.0;
  options.boresight_deg.setZero();
  return options;
}

Eigen::Vector3d Centre(const SurveyStation& station) {
  return station.cam_from_world.Inverse().translation;
}

Eigen::Vector3d OpticalAxis(const SurveyStation& station) {
  return station.cam_from_world.Inverse().RotationMatrix().col(2);
}

TEST(Survey, LawnmowerSpacingFollowsFootprintAndOverlap) {
  const World world = PlaneWorld(Eigen::Vector3d::UnitZ(),
                                 Eigen::Vector3d::UnitX(), 20.0, 12.0);
  const SurveyOptions options = NoJitter();
  const auto stations =
      PlanSurvey(SurveyKind::kLawnmower, world, TestCamera(), options, 1);
  // Footprint at 2.5 m: 2.5 m across (image x, 1000 px), 2.0 m along.
  const double along_spacing = 2.0 * (1.0 - options.forward_overlap);
  const double pass_spacing = 2.5 * (1.0 - options.side_overlap);
  ASSERT_GT(stations.size(), 20u);
  int num_passes = 0;
  for (size_t i = 0; i < stations.size(); ++i) {
    const Eigen::Vector3d centre = Centre(stations[i]);
    EXPECT_NEAR((centre - world.survey_origin).dot(world.survey_normal),
                options.distance_m, 1e-9);
    EXPECT_NEAR(OpticalAxis(stations[i]).dot(-world.survey_normal), 1.0, 1e-12);
    if (i == 0) continue;
    EXPECT_GT(stations[i].time_s, stations[i - 1].time_s);
    const Eigen::Vector3d step = centre - Centre(stations[i - 1]);
    if (stations[i].pass == stations[i - 1].pass) {
      EXPECT_NEAR(step.norm(), along_spacing, 1e-9);
    } else {
      ++num_passes;
      EXPECT_NEAR(std::abs(step.y()), pass_spacing, 1e-9);
    }
  }
  EXPECT_GE(num_passes, 3);
  // Back and forth: the second pass runs against the first.
  EXPECT_GT(Centre(stations[1]).x(), Centre(stations[0]).x());
  const size_t first_of_second =
      std::find_if(stations.begin(), stations.end(),
                   [](const SurveyStation& s) { return s.pass == 1; }) -
      stations.begin();
  EXPECT_LT(Centre(stations[first_of_second + 1]).x(),
            Centre(stations[first_of_second]).x());
}

TEST(Survey, SinglePassAlongAWallLooksAtItUpright) {
  const World world = PlaneWorld(-Eigen::Vector3d::UnitY(),
                                 Eigen::Vector3d::UnitX(), 300.0, 10.0);
  SurveyOptions options = NoJitter();
  options.coverage_along = 0.2;
  const auto stations =
      PlanSurvey(SurveyKind::kSinglePass, world, TestCamera(), options, 1);
  ASSERT_GT(stations.size(), 50u);
  for (const SurveyStation& station : stations) {
    EXPECT_EQ(station.pass, 0);
    EXPECT_NEAR(OpticalAxis(station).dot(Eigen::Vector3d::UnitY()), 1.0, 1e-12);
    // Image "down" is world down.
    const Eigen::Vector3d down =
        station.cam_from_world.Inverse().RotationMatrix().col(1);
    EXPECT_NEAR(down.z(), -1.0, 1e-12);
    EXPECT_NEAR(Centre(station).y(), world.survey_origin.y() - 2.5, 1e-9);
  }
  EXPECT_NEAR((Centre(stations.back()) - Centre(stations.front())).norm(),
              0.2 * 300.0 - 2.5, 0.5 * 2.5 * 0.25 + 1e-9);
}

TEST(Survey, CameraSitsOnTheVehicleAsMounted) {
  const World world = PlaneWorld(Eigen::Vector3d::UnitZ(),
                                 Eigen::Vector3d::UnitX(), 20.0, 12.0);
  const SurveyOptions options;  // with jitter, lever arm and boresight
  const Rigid3d vehicle_from_cam = VehicleFromCam(world, options);
  for (const SurveyStation& station :
       PlanSurvey(SurveyKind::kLawnmower, world, TestCamera(), options, 7)) {
    const Eigen::Matrix3d world_from_vehicle =
        WorldFromVehicleRotation(station.vehicle_rpy);
    const Rigid3d world_from_cam = station.cam_from_world.Inverse();
    EXPECT_LT((world_from_cam.translation -
               (world_from_vehicle * vehicle_from_cam.translation +
                station.vehicle_position))
                  .norm(),
              1e-12);
    EXPECT_LT((world_from_cam.RotationMatrix() -
               world_from_vehicle * vehicle_from_cam.RotationMatrix())
                  .norm(),
              1e-12);
  }
}

TEST(Survey, JitterHasTheConfiguredSpreadAndIsSeeded) {
  const World world = PlaneWorld(Eigen::Vector3d::UnitZ(),
                                 Eigen::Vector3d::UnitX(), 60.0, 40.0);
  SurveyOptions options;
  options.attitude_jitter_deg = 2.0;
  const auto a =
      PlanSurvey(SurveyKind::kLawnmower, world, TestCamera(), options, 3);
  const auto b =
      PlanSurvey(SurveyKind::kLawnmower, world, TestCamera(), options, 3);
  const auto c =
      PlanSurvey(SurveyKind::kLawnmower, world, TestCamera(), options, 4);
  ASSERT_EQ(a.size(), b.size());
  double sum_squares = 0.0;
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].vehicle_position, b[i].vehicle_position);
    EXPECT_EQ(a[i].vehicle_rpy, b[i].vehicle_rpy);
    sum_squares += a[i].vehicle_rpy.x() * a[i].vehicle_rpy.x();
  }
  EXPECT_NE(a[0].vehicle_position, c[0].vehicle_position);
  const double roll_sigma = std::sqrt(sum_squares / a.size());
  EXPECT_NEAR(roll_sigma, 2.0 * kDegToRad, 0.25 * 2.0 * kDegToRad)
      << a.size() << " stations";
}

TEST(Survey, RollPitchYawRoundTrip) {
  for (const Eigen::Vector3d& rpy :
       {Eigen::Vector3d(0.1, -0.2, 3.0), Eigen::Vector3d(-1.0, 0.5, -2.5),
        Eigen::Vector3d(0.0, 0.0, 0.0)}) {
    EXPECT_LT(
        (RollPitchYawFromRotation(WorldFromVehicleRotation(rpy)) - rpy).norm(),
        1e-12);
  }
}

TEST(Survey, OptionsAreCheckedAndRoundTripThroughJson) {
  SurveyOptions options;
  options.distance_m = 3.25;
  options.lever_arm_m = Eigen::Vector3d(1, 2, 3);
  nlohmann::json json = options;
  SurveyOptions read;
  json.get_to(read);
  EXPECT_EQ(read.distance_m, 3.25);
  EXPECT_EQ(read.lever_arm_m, options.lever_arm_m);
  json["typo"] = 1;
  EXPECT_THROW(json.get_to(read), Error);
  SurveyOptions bad;
  bad.forward_overlap = 1.2;
  EXPECT_THROW(bad.Check(), Error);
  bad = SurveyOptions();
  bad.distance_m = std::nan("");
  EXPECT_THROW(bad.Check(), Error);
  EXPECT_THROW(SurveyKindFromName("zigzag"), Error);
}

}  // namespace
}  // namespace uw::sim
