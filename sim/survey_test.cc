#include "sim/survey.h"

#include <gtest/gtest.h>

#include <iomanip>
#include <map>
#include <set>
#include <sstream>

#include "common/mesh/ray_caster.h"
#include "common/mesh/test_meshes.h"
#include "common/util/error.h"
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

std::string ImageName(size_t index) {
  std::ostringstream name;
  name << std::setw(5) << std::setfill('0') << index;
  return name.str();
}

Eigen::Matrix3d WorldFromCamRotation(const SurveyStation& station) {
  return station.cam_from_world.Inverse().RotationMatrix();
}

// A 24 x 24 m plane through `point` with unit `normal`, meshed at 0.2 m,
// as the world's mesh; the survey frame stays that of PlaneWorld.
World MeshPlaneWorld(const Eigen::Vector3d& point,
                     const Eigen::Vector3d& normal) {
  World world = PlaneWorld(Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX(),
                           20.0, 12.0);
  // u: x made perpendicular to the normal; u x v along the normal.
  const Eigen::Vector3d u =
      24.0 * normal.cross(Eigen::Vector3d::UnitX()).cross(normal).normalized();
  const Eigen::Vector3d v = normal.cross(u);
  AddGrid(point - 0.5 * u - 0.5 * v, u, v, 120, 120, &world.mesh);
  return world;
}

// Where the image's corners see the plane z = height: the footprint.
std::vector<Eigen::Vector2d> FootprintOnPlane(const SurveyStation& station,
                                              const Camera& camera,
                                              double height) {
  const Rigid3d world_from_cam = station.cam_from_world.Inverse();
  const double f = camera.params[0];
  const double cx = camera.params[2];
  const double cy = camera.params[3];
  std::vector<Eigen::Vector2d> corners;
  for (const Eigen::Vector2d& pixel :
       {Eigen::Vector2d(0, 0), Eigen::Vector2d(camera.width, 0),
        Eigen::Vector2d(camera.width, camera.height),
        Eigen::Vector2d(0, camera.height)}) {
    const Eigen::Vector3d ray =
        world_from_cam.RotationMatrix() *
        Eigen::Vector3d((pixel.x() - cx) / f, (pixel.y() - cy) / f, 1.0);
    const Eigen::Vector3d hit =
        world_from_cam.translation +
        (height - world_from_cam.translation.z()) / ray.z() * ray;
    corners.push_back(hit.head<2>());
  }
  return corners;
}

bool InsideConvex(const std::vector<Eigen::Vector2d>& polygon,
                  const Eigen::Vector2d& point) {
  int sign = 0;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Eigen::Vector2d edge = polygon[(i + 1) % polygon.size()] - polygon[i];
    const Eigen::Vector2d to_point = point - polygon[i];
    const int side =
        edge.x() * to_point.y() - edge.y() * to_point.x() > 0.0 ? 1 : -1;
    if (sign != 0 && side != sign) return false;
    sign = side;
  }
  return true;
}

// Area (m^2) seen by each dive on the plane z = height, and by each pair of
// dives, counted on a 5 cm grid.
struct DiveCoverage {
  std::map<int, double> area;
  std::map<std::pair<int, int>, double> shared;
};

DiveCoverage MeasureDiveCoverage(const std::vector<SurveyStation>& stations,
                                 const Camera& camera, double height) {
  std::map<int, std::vector<std::vector<Eigen::Vector2d>>> footprints;
  Eigen::AlignedBox2d bounds;
  for (const SurveyStation& station : stations) {
    footprints[station.dive].push_back(
        FootprintOnPlane(station, camera, height));
    for (const Eigen::Vector2d& corner : footprints[station.dive].back()) {
      bounds.extend(corner);
    }
  }
  const double cell = 0.05;
  DiveCoverage coverage;
  for (double x = bounds.min().x(); x < bounds.max().x(); x += cell) {
    for (double y = bounds.min().y(); y < bounds.max().y(); y += cell) {
      std::set<int> seen_by;
      for (const auto& [dive, polygons] : footprints) {
        for (const auto& polygon : polygons) {
          if (InsideConvex(polygon, Eigen::Vector2d(x, y))) {
            seen_by.insert(dive);
            break;
          }
        }
      }
      for (const int a : seen_by) {
        coverage.area[a] += cell * cell;
        for (const int b : seen_by) {
          if (a < b) coverage.shared[{a, b}] += cell * cell;
        }
      }
    }
  }
  return coverage;
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
  const World world =
      MeshPlaneWorld(Eigen::Vector3d(5.0, -3.0, 0.2),
                     Eigen::Vector3d(0.1, -0.2, 1).normalized());
  SurveyOptions options;  // with jitter, lever arm and boresight
  options.views_jitter = true;
  const Rigid3d vehicle_from_cam = VehicleFromCam(world, options);
  std::vector<SurveyStation> stations;
  for (const SurveyKind kind :
       {SurveyKind::kLawnmower, SurveyKind::kSinglePass, SurveyKind::kMultiDive,
        SurveyKind::kVideo, SurveyKind::kViews}) {
    const auto planned = PlanSurvey(kind, world, TestCamera(), options, 7);
    EXPECT_GT(planned.size(), 5u) << SurveyKindName(kind);
    stations.insert(stations.end(), planned.begin(), planned.end());
  }
  for (const SurveyStation& station : stations) {
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

// What truth/sim.json tells the importer: a floor is imaged down, a wall
// to starboard; the mount's rotation is the one the stations carry.
TEST(Survey, CameraMountIsDownOverAFloorAndStarboardAtAWall) {
  const World floor =
      MeshPlaneWorld(Eigen::Vector3d(5.0, -3.0, 0.2), Eigen::Vector3d::UnitZ());
  const World wall = PlaneWorld(-Eigen::Vector3d::UnitY(),
                                Eigen::Vector3d::UnitX(), 300.0, 10.0);
  EXPECT_EQ(SurveyCameraMount(floor), CameraMount::kDown);
  EXPECT_EQ(SurveyCameraMount(wall), CameraMount::kStarboard);
  SurveyOptions options = NoJitter();
  options.boresight_deg.setZero();
  for (const World* world : {&floor, &wall}) {
    EXPECT_LT((VehicleFromCam(*world, options).RotationMatrix() -
               NominalVehicleFromCamRotation(SurveyCameraMount(*world)))
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
  for (const SurveyKind kind :
       {SurveyKind::kLawnmower, SurveyKind::kSinglePass, SurveyKind::kMultiDive,
        SurveyKind::kVideo, SurveyKind::kViews}) {
    EXPECT_EQ(SurveyKindFromName(SurveyKindName(kind)), kind);
  }
}

TEST(Survey, NewOptionsAreCheckedAndRoundTripThroughJson) {
  SurveyOptions options;
  EXPECT_FALSE(options.views_target.has_value());
  nlohmann::json json = options;
  EXPECT_TRUE(json.at("views_target").is_null());
  options.views_target = Eigen::Vector3d(1.5, -2, 3);
  options.num_dives = 3;
  options.frame_rate_hz = 4.0;
  json = options;
  SurveyOptions read;
  json.get_to(read);
  ASSERT_TRUE(read.views_target.has_value());
  EXPECT_EQ(*read.views_target, Eigen::Vector3d(1.5, -2, 3));
  EXPECT_EQ(read.num_dives, 3);
  EXPECT_EQ(read.frame_rate_hz, 4.0);
  // Absent keeps the value, null unsets it.
  nlohmann::json partial = {{"num_dives", 2}};
  partial.get_to(read);
  EXPECT_TRUE(read.views_target.has_value());
  partial["views_target"] = nullptr;
  partial.get_to(read);
  EXPECT_FALSE(read.views_target.has_value());
  partial["views_target"] = {1, 2};
  EXPECT_THROW(partial.get_to(read), Error);

  const auto expect_bad = [](auto change) {
    SurveyOptions bad;
    change(bad);
    EXPECT_THROW(bad.Check(), Error);
  };
  expect_bad([](SurveyOptions& o) { o.num_dives = 1; });
  expect_bad([](SurveyOptions& o) { o.num_dives = 6; });
  expect_bad([](SurveyOptions& o) { o.dive_overlap = 1.0; });
  expect_bad([](SurveyOptions& o) { o.dive_gap_s = -1.0; });
  expect_bad([](SurveyOptions& o) { o.frame_rate_hz = 0.0; });
  expect_bad([](SurveyOptions& o) { o.views_distance_m = 0.0; });
  expect_bad([](SurveyOptions& o) { o.views_step_deg = 3.0; });  // 40 / 3
  expect_bad([](SurveyOptions& o) { o.views_max_angle_deg = 85.0; });
  expect_bad([](SurveyOptions& o) { o.views_normal_radius_m = 0.0; });
  expect_bad([](SurveyOptions& o) {
    o.views_target = Eigen::Vector3d(0, std::nan(""), 0);
  });
}

// The views' relative rotation world_from_cam_0^T world_from_cam =
// AngleAxis(pitch, -x) AngleAxis(roll, -y) = Rx(-pitch) Ry(-roll).
Eigen::Vector2d PitchRoll(const Eigen::Matrix3d& relative) {
  return Eigen::Vector2d(-std::atan2(relative(2, 1), relative(1, 1)),
                         -std::atan2(relative(0, 2), relative(0, 0)));
}

TEST(Survey, ViewsLookAtTheTargetOverTheThesisGrid) {
  // The surface under survey_origin (5, -3, 0.5) is tilted 20 deg from the
  // survey normal, so the views' normal is not the survey's.
  const Eigen::Vector3d target(5.0, -3.0, 0.2);
  const double tilt = 20.0 * kDegToRad;
  const Eigen::Vector3d normal(0.0, -std::sin(tilt), std::cos(tilt));
  const World world = MeshPlaneWorld(target, normal);
  SurveyOptions options;  // default jitter, lever arm and boresight
  const auto stations =
      PlanSurvey(SurveyKind::kViews, world, TestCamera(), options, 1);
  ASSERT_EQ(stations.size(), 289u);
  const RayCaster caster(world.mesh);
  size_t square = 0;
  double best_alignment = -1.0;
  for (size_t i = 0; i < stations.size(); ++i) {
    const SurveyStation& station = stations[i];
    EXPECT_EQ(station.image_name, ImageName(i));
    EXPECT_EQ(station.dive, 1);
    const Eigen::Vector3d centre = Centre(station);
    const Eigen::Vector3d axis = OpticalAxis(station);
    EXPECT_NEAR((target - centre).norm(), options.views_distance_m, 1e-9);
    EXPECT_LT((centre + options.views_distance_m * axis - target).norm(), 1e-9);
    const auto hit = caster.Intersect(centre, axis);
    ASSERT_TRUE(hit.has_value());
    EXPECT_LT((hit->point_in_world - target).norm(), 1e-9);
    EXPECT_NEAR(hit->distance, options.views_distance_m, 1e-9);
    if (i > 0) {
      EXPECT_GT(station.time_s, stations[i - 1].time_s);
    }
    const double alignment = axis.dot(-normal);
    if (alignment > best_alignment) {
      best_alignment = alignment;
      square = i;
    }
  }
  // The 0/0 view looks straight down the surface normal.
  EXPECT_NEAR(best_alignment, 1.0, 1e-12);
  const Eigen::Matrix3d world_from_cam_0 =
      WorldFromCamRotation(stations[square]);
  std::set<std::pair<int, int>> grid;
  Eigen::Vector2d min_angles = Eigen::Vector2d::Constant(1e9);
  Eigen::Vector2d max_angles = -min_angles;
  for (const SurveyStation& station : stations) {
    const Eigen::Vector2d angles = PitchRoll(world_from_cam_0.transpose() *
                                             WorldFromCamRotation(station)) /
                                   kDegToRad;
    const Eigen::Vector2d steps = angles / 5.0;
    EXPECT_LT((steps - steps.array().round().matrix()).norm(), 1e-9);
    grid.insert({static_cast<int>(std::lround(steps.x())),
                 static_cast<int>(std::lround(steps.y()))});
    min_angles = min_angles.cwiseMin(angles);
    max_angles = max_angles.cwiseMax(angles);
    // The tilt from the normal is that of the pitch and roll.
    EXPECT_NEAR(
        OpticalAxis(station).dot(-normal),
        std::cos(angles.x() * kDegToRad) * std::cos(angles.y() * kDegToRad),
        1e-12);
  }
  EXPECT_EQ(grid.size(), 289u);  // every pitch with every roll, once
  EXPECT_LT((min_angles - Eigen::Vector2d(-40, -40)).norm(), 1e-9);
  EXPECT_LT((max_angles - Eigen::Vector2d(40, 40)).norm(), 1e-9);
}

TEST(Survey, ViewsOnALevelFloorAreTheVehiclesPitchAndRoll) {
  const World world =
      MeshPlaneWorld(Eigen::Vector3d(0, 0, -1.0), Eigen::Vector3d::UnitZ());
  SurveyOptions options = NoJitter();
  options.views_max_angle_deg = 10.0;
  options.views_distance_m = 2.0;
  const auto stations =
      PlanSurvey(SurveyKind::kViews, world, TestCamera(), options, 1);
  ASSERT_EQ(stations.size(), 25u);
  std::set<std::pair<int, int>> grid;
  for (const SurveyStation& station : stations) {
    const Eigen::Vector3d degrees = station.vehicle_rpy / kDegToRad;
    EXPECT_NEAR(degrees.z(), 0.0, 1e-9);  // heading along survey_along
    EXPECT_NEAR(degrees.x() / 5.0, std::round(degrees.x() / 5.0), 1e-9);
    EXPECT_NEAR(degrees.y() / 5.0, std::round(degrees.y() / 5.0), 1e-9);
    grid.insert({static_cast<int>(std::lround(degrees.y())),
                 static_cast<int>(std::lround(degrees.x()))});
    // Pitch by pitch, the roll going back and forth.
    EXPECT_EQ(station.pass, std::lround(degrees.y()) / 5 + 2);
    EXPECT_LT((Centre(station) + 2.0 * OpticalAxis(station) -
               Eigen::Vector3d(5.0, -3.0, -1.0))
                  .norm(),
              1e-9);
  }
  EXPECT_EQ(grid.size(), 25u);
  // Consecutive views differ by one step of one angle: a continuous track.
  for (size_t i = 1; i < stations.size(); ++i) {
    const Eigen::Vector3d change =
        (stations[i].vehicle_rpy - stations[i - 1].vehicle_rpy) / kDegToRad;
    EXPECT_NEAR(change.head<2>().lpNorm<1>(), 5.0, 1e-9) << i;
  }
}

TEST(Survey, ViewsUseTheMeanNormalAroundTheTarget) {
  // A ridge along x through (0, 0, 1): flanks dipping 25 deg each way. The
  // facet under the target is tilted 25 deg; the mean normal is +z.
  const double slope = std::tan(25.0 * kDegToRad);
  TriangleMesh flank;
  AddGrid(Eigen::Vector3d(-3, -2, 1 - 2 * slope), Eigen::Vector3d(6, 0, 0),
          Eigen::Vector3d(0, 2, 2 * slope), 60, 20, &flank);
  World world =
      PlaneWorld(Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX(), 6.0, 4.0);
  world.mesh = flank;
  // The other flank is the mirror image (y -> -y, winding reversed), so
  // that the neighbourhood is exactly symmetric.
  const int offset = static_cast<int>(flank.vertices.size());
  for (const Eigen::Vector3d& vertex : flank.vertices) {
    world.mesh.vertices.emplace_back(vertex.x(), -vertex.y(), vertex.z());
  }
  for (const Eigen::Vector3i& triangle : flank.triangles) {
    world.mesh.triangles.emplace_back(
        triangle[0] + offset, triangle[2] + offset, triangle[1] + offset);
  }
  SurveyOptions options = NoJitter();
  options.views_target = Eigen::Vector3d(0.5, 0.0, 1.0);
  options.views_max_angle_deg = 0.0;
  const auto level =
      PlanSurvey(SurveyKind::kViews, world, TestCamera(), options, 1);
  ASSERT_EQ(level.size(), 1u);
  EXPECT_NEAR(OpticalAxis(level[0]).dot(-Eigen::Vector3d::UnitZ()), 1.0, 1e-12);
  // Off the ridge by more than the radius, the mean is the flank's normal.
  options.views_target = Eigen::Vector3d(0.5, -1.0, 1.0 - slope);
  options.views_normal_radius_m = 0.3;
  const auto flank_view =
      PlanSurvey(SurveyKind::kViews, world, TestCamera(), options, 1);
  ASSERT_EQ(flank_view.size(), 1u);
  EXPECT_NEAR(OpticalAxis(flank_view[0])
                  .dot(-Eigen::Vector3d(0, -slope, 1).normalized()),
              1.0, 1e-12);
}

TEST(Survey, ViewsRefuseTargetsTheyCannotLookAt) {
  SurveyOptions options = NoJitter();
  // No mesh.
  EXPECT_THROW(PlanSurvey(SurveyKind::kViews,
                          PlaneWorld(Eigen::Vector3d::UnitZ(),
                                     Eigen::Vector3d::UnitX(), 20.0, 12.0),
                          TestCamera(), options, 1),
               Error);
  // A surface tilted 60 deg about the vehicle's y axis: pitching 40 deg
  // more would pass 85 deg.
  const World steep = MeshPlaneWorld(
      Eigen::Vector3d(5.0, -3.0, 0.2),
      Eigen::Vector3d(std::sin(60 * kDegToRad), 0, std::cos(60 * kDegToRad)));
  EXPECT_THROW(PlanSurvey(SurveyKind::kViews, steep, TestCamera(), options, 1),
               Error);
  options.views_max_angle_deg = 20.0;
  EXPECT_EQ(
      PlanSurvey(SurveyKind::kViews, steep, TestCamera(), options, 1).size(),
      81u);
  // A target far from the mesh has no normal.
  options.views_target = Eigen::Vector3d(5.0, -3.0, 5.0);
  EXPECT_THROW(PlanSurvey(SurveyKind::kViews, steep, TestCamera(), options, 1),
               Error);
}

TEST(Survey, MultiDiveCrossesOverlappingPartsWithAGap) {
  const World world = PlaneWorld(Eigen::Vector3d::UnitZ(),
                                 Eigen::Vector3d::UnitX(), 20.0, 12.0);
  const Camera camera = TestCamera();
  for (const int num_dives : {2, 3}) {
    SurveyOptions options = NoJitter();
    options.num_dives = num_dives;
    const auto stations =
        PlanSurvey(SurveyKind::kMultiDive, world, camera, options, 1);
    ASSERT_FALSE(stations.empty());
    EXPECT_EQ(stations.front().dive, 1);
    EXPECT_EQ(stations.back().dive, num_dives);
    for (size_t i = 1; i < stations.size(); ++i) {
      const SurveyStation& a = stations[i - 1];
      const SurveyStation& b = stations[i];
      EXPECT_EQ(b.image_name, ImageName(i));
      ASSERT_GE(b.dive, a.dive);
      ASSERT_LE(b.dive, a.dive + 1);
      if (b.dive == a.dive) {
        EXPECT_GT(b.time_s, a.time_s);
        EXPECT_LT(b.time_s - a.time_s, 100.0);
      } else {
        EXPECT_NEAR(b.time_s - a.time_s, options.dive_gap_s, 1e-9);
      }
    }
    for (const SurveyStation& station : stations) {
      // Odd dives fly along the survey axis (x), even ones across it.
      const double heading = station.vehicle_rpy.z();
      if (station.dive % 2 == 1) {
        EXPECT_NEAR(std::abs(std::cos(heading)), 1.0, 1e-12);
      } else {
        EXPECT_NEAR(std::abs(std::sin(heading)), 1.0, 1e-12);
      }
      EXPECT_NEAR(Centre(station).z(),
                  world.survey_origin.z() + options.distance_m, 1e-9);
    }
    const DiveCoverage coverage =
        MeasureDiveCoverage(stations, camera, world.survey_origin.z());
    for (int dive = 1; dive < num_dives; ++dive) {
      const double shared = coverage.shared.at({dive, dive + 1});
      EXPECT_GT(shared / coverage.area.at(dive), 0.25) << dive;
      EXPECT_LT(shared / coverage.area.at(dive), 0.5) << dive;
      EXPECT_GT(shared / coverage.area.at(dive + 1), 0.25) << dive;
      EXPECT_LT(shared / coverage.area.at(dive + 1), 0.5) << dive;
    }
    // Together the dives cover the area a lawnmower would.
    double total = 0.0;
    for (const auto& [dive, area] : coverage.area) total += area;
    for (const auto& [dives, area] : coverage.shared) total -= area;
    EXPECT_NEAR(total, 0.7 * 20.0 * 0.7 * 12.0, 0.15 * 0.7 * 20.0 * 0.7 * 12.0);
  }
}

TEST(Survey, MultiDiveOverlapFollowsTheOption) {
  const World world = PlaneWorld(Eigen::Vector3d::UnitZ(),
                                 Eigen::Vector3d::UnitX(), 20.0, 12.0);
  std::vector<double> fractions;
  for (const double overlap : {0.2, 0.6}) {
    SurveyOptions options = NoJitter();
    options.dive_overlap = overlap;
    const DiveCoverage coverage = MeasureDiveCoverage(
        PlanSurvey(SurveyKind::kMultiDive, world, TestCamera(), options, 1),
        TestCamera(), world.survey_origin.z());
    fractions.push_back(coverage.shared.at({1, 2}) / coverage.area.at(1));
    EXPECT_NEAR(fractions.back(), overlap, 0.12) << overlap;
  }
  EXPECT_GT(fractions[1] - fractions[0], 0.3);
}

TEST(Survey, VideoFramesAreEvenlySpacedAlongAContinuousTrack) {
  const World world = PlaneWorld(Eigen::Vector3d::UnitZ(),
                                 Eigen::Vector3d::UnitX(), 20.0, 12.0);
  SurveyOptions options = NoJitter();
  options.speed_m_per_s = 0.5;
  options.frame_rate_hz = 2.0;
  const double spacing = 0.25;
  const auto stations =
      PlanSurvey(SurveyKind::kVideo, world, TestCamera(), options, 1);
  // Lines as long as the covered area less a footprint (2 m along), 1 m
  // apart (2.5 m footprint, 60 % side overlap) over 0.7 * 12 - 2.5 m:
  // 6 lines of 12 m and 5 half-circle turns of radius 0.5 m.
  const double line_length = 0.7 * 20.0 - 2.0;
  const int num_lines = 6;
  const double radius = 0.5;
  const double track_length =
      num_lines * line_length + (num_lines - 1) * M_PI * radius;
  ASSERT_EQ(stations.size(),
            static_cast<size_t>(std::floor(track_length / spacing)) + 1);
  EXPECT_LT((Centre(stations.front()) -
             (world.survey_origin + Eigen::Vector3d(-6.0, -2.5, 2.5)))
                .norm(),
            1e-9);
  EXPECT_EQ(stations.back().pass, num_lines - 1);
  const double min_chord = 2.0 * radius * std::sin(0.5 * spacing / radius);
  int num_straight = 0;
  int num_turning = 0;
  for (size_t i = 0; i < stations.size(); ++i) {
    const SurveyStation& station = stations[i];
    EXPECT_NEAR(station.time_s, i / options.frame_rate_hz, 1e-12);
    EXPECT_NEAR(Centre(station).z(),
                world.survey_origin.z() + options.distance_m, 1e-9);
    if (i == 0) continue;
    const SurveyStation& before = stations[i - 1];
    const Eigen::Vector3d step = Centre(station) - Centre(before);
    // Frames follow the track: exactly the spacing on a line, a chord of
    // it on a turn; the heading turns by at most the arc's angle.
    EXPECT_LE(step.norm(), spacing + 1e-9);
    EXPECT_GE(step.norm(), min_chord - 1e-9);
    const double turn = std::abs(std::remainder(
        station.vehicle_rpy.z() - before.vehicle_rpy.z(), 2.0 * M_PI));
    EXPECT_LE(turn, spacing / radius + 1e-9);
    if (turn == 0.0) {
      ++num_straight;
      EXPECT_NEAR(step.norm(), spacing, 1e-9);
      EXPECT_NEAR(std::abs(step.normalized().dot(
                      WorldFromVehicleRotation(station.vehicle_rpy).col(0))),
                  1.0, 1e-12);
    } else {
      ++num_turning;
    }
    EXPECT_GE(station.pass, before.pass);
  }
  EXPECT_GT(num_straight, 250);
  EXPECT_GE(num_turning, 5 * 5);  // pi * 0.5 m / 0.25 m per turn
}

TEST(Survey, VideoAlongAWallKeepsItsHeadingAndMovesUpBetweenLines) {
  const World world = PlaneWorld(-Eigen::Vector3d::UnitY(),
                                 Eigen::Vector3d::UnitX(), 30.0, 10.0);
  SurveyOptions options = NoJitter();
  const auto stations =
      PlanSurvey(SurveyKind::kVideo, world, TestCamera(), options, 1);
  ASSERT_GT(stations.size(), 50u);
  const double spacing = options.speed_m_per_s / options.frame_rate_hz;
  std::set<int> passes;
  for (size_t i = 0; i < stations.size(); ++i) {
    passes.insert(stations[i].pass);
    EXPECT_NEAR(OpticalAxis(stations[i]).dot(Eigen::Vector3d::UnitY()), 1.0,
                1e-12);
    EXPECT_NEAR(stations[i].vehicle_rpy.z(), stations.front().vehicle_rpy.z(),
                1e-12);
    if (i == 0) continue;
    const Eigen::Vector3d step = Centre(stations[i]) - Centre(stations[i - 1]);
    EXPECT_LE(step.norm(), spacing + 1e-9);
    // Off a corner, exactly the spacing along x or up z.
    if (std::abs(step.x()) < 1e-12 || std::abs(step.z()) < 1e-12) {
      EXPECT_NEAR(step.norm(), spacing, 1e-9);
    }
  }
  EXPECT_GE(passes.size(), 3u);
}

}  // namespace
}  // namespace uw::sim
