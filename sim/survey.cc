#include "sim/survey.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <random>
#include <sstream>

#include "colmap_plugins/util/error.h"
#include "sim/json_fields.h"
#include "sim/world.h"

namespace uw::sim {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

bool IsFinitePositive(double value) {
  return std::isfinite(value) && value > 0.0;
}

void CheckFraction(double value, const char* name, double min, double max) {
  if (!(value >= min && value <= max)) {
    throw ErrorAt("survey option ", name, " = ", value, " must be in [", min,
                  ", ", max, "]");
  }
}

// Whether the camera looks down (floor) or sideways (wall) follows from how
// steep the survey plane is.
bool IsWallSurvey(const World& world) {
  return std::abs(world.survey_normal.z()) < 0.7;
}

// Nominal camera mounts, columns = camera axes in the vehicle frame.
Eigen::Matrix3d DownMount() {
  // Image top towards the bow: camera y = −x, z = −z, x = y × z = −y.
  Eigen::Matrix3d vehicle_from_cam;
  vehicle_from_cam.col(0) = -Eigen::Vector3d::UnitY();
  vehicle_from_cam.col(1) = -Eigen::Vector3d::UnitX();
  vehicle_from_cam.col(2) = -Eigen::Vector3d::UnitZ();
  return vehicle_from_cam;
}

Eigen::Matrix3d StarboardMount() {
  // Looking to starboard with the image upright: camera z = −y, y = −z,
  // x = y × z = −x.
  Eigen::Matrix3d vehicle_from_cam;
  vehicle_from_cam.col(0) = -Eigen::Vector3d::UnitX();
  vehicle_from_cam.col(1) = -Eigen::Vector3d::UnitZ();
  vehicle_from_cam.col(2) = -Eigen::Vector3d::UnitY();
  return vehicle_from_cam;
}

Rigid3d MakeVehicleFromCam(bool wall, const SurveyOptions& options) {
  const Eigen::Matrix3d boresight =
      WorldFromVehicleRotation(options.boresight_deg * kDegToRad);
  Rigid3d vehicle_from_cam;
  vehicle_from_cam.rotation =
      Eigen::Quaterniond((wall ? StarboardMount() : DownMount()) * boresight);
  vehicle_from_cam.translation = options.lever_arm_m;
  return vehicle_from_cam;
}

// Image footprint (m) along the camera's x and y axes at distance d.
Eigen::Vector2d Footprint(const Camera& camera, double distance) {
  const double w = static_cast<double>(camera.width);
  const double h = static_cast<double>(camera.height);
  const auto ray = [&](double x, double y) {
    return CameraModelCamFromImg(camera.model_id, camera.params.data(),
                                 Eigen::Vector2d(x, y));
  };
  return distance * Eigen::Vector2d(ray(w, 0.5 * h).x() - ray(0, 0.5 * h).x(),
                                    ray(0.5 * w, h).y() - ray(0.5 * w, 0).y());
}

// Positions of `count` stations spread evenly over [-half, half].
std::vector<double> Spread(double half, double spacing) {
  const int count =
      std::max(1, static_cast<int>(std::floor(2.0 * half / spacing)) + 1);
  std::vector<double> positions;
  const double start = -0.5 * spacing * (count - 1);
  for (int i = 0; i < count; ++i) positions.push_back(start + i * spacing);
  return positions;
}

}  // namespace

std::string SurveyKindName(SurveyKind kind) {
  return kind == SurveyKind::kLawnmower ? "lawnmower" : "single_pass";
}

SurveyKind SurveyKindFromName(const std::string& name) {
  if (name == "lawnmower") return SurveyKind::kLawnmower;
  if (name == "single_pass") return SurveyKind::kSinglePass;
  throw ErrorAt("unknown survey '", name,
                "' (available: lawnmower, single_pass)");
}

void SurveyOptions::Check() const {
  if (!IsFinitePositive(distance_m)) {
    throw ErrorAt("survey option distance_m = ", distance_m,
                  " must be positive");
  }
  CheckFraction(forward_overlap, "forward_overlap", 0.0, 0.95);
  CheckFraction(side_overlap, "side_overlap", 0.0, 0.95);
  CheckFraction(coverage_along, "coverage_along", 0.01, 1.0);
  CheckFraction(coverage_across, "coverage_across", 0.0, 1.0);
  if (!IsFinitePositive(speed_m_per_s)) {
    throw ErrorAt("survey option speed_m_per_s = ", speed_m_per_s,
                  " must be positive");
  }
  CheckFraction(attitude_jitter_deg, "attitude_jitter_deg", 0.0, 30.0);
  CheckFraction(position_jitter_m, "position_jitter_m", 0.0, distance_m / 2);
  if (!lever_arm_m.allFinite() || !boresight_deg.allFinite()) {
    throw ErrorAt(
        "survey options lever_arm_m and boresight_deg must be "
        "finite");
  }
  if (max_images < 0) {
    throw ErrorAt("survey option max_images = ", max_images, " must be >= 0");
  }
}

void to_json(nlohmann::json& json, const SurveyOptions& options) {
  json = {{"distance_m", options.distance_m},
          {"forward_overlap", options.forward_overlap},
          {"side_overlap", options.side_overlap},
          {"coverage_along", options.coverage_along},
          {"coverage_across", options.coverage_across},
          {"speed_m_per_s", options.speed_m_per_s},
          {"attitude_jitter_deg", options.attitude_jitter_deg},
          {"position_jitter_m", options.position_jitter_m},
          {"lever_arm_m", ToJson(options.lever_arm_m)},
          {"boresight_deg", ToJson(options.boresight_deg)},
          {"max_images", options.max_images}};
}

void from_json(const nlohmann::json& json, SurveyOptions& options) {
  JsonFields fields(json, "survey_options");
  fields.Read("distance_m", &options.distance_m);
  fields.Read("forward_overlap", &options.forward_overlap);
  fields.Read("side_overlap", &options.side_overlap);
  fields.Read("coverage_along", &options.coverage_along);
  fields.Read("coverage_across", &options.coverage_across);
  fields.Read("speed_m_per_s", &options.speed_m_per_s);
  fields.Read("attitude_jitter_deg", &options.attitude_jitter_deg);
  fields.Read("position_jitter_m", &options.position_jitter_m);
  fields.Read("lever_arm_m", &options.lever_arm_m);
  fields.Read("boresight_deg", &options.boresight_deg);
  fields.Read("max_images", &options.max_images);
  fields.RejectUnknown();
}

Eigen::Matrix3d WorldFromVehicleRotation(const Eigen::Vector3d& rpy) {
  return (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Eigen::Vector3d RollPitchYawFromRotation(const Eigen::Matrix3d& rotation) {
  // R = Rz(yaw) Ry(pitch) Rx(roll): R(2,0) = -sin(pitch).
  const double pitch = std::asin(std::clamp(-rotation(2, 0), -1.0, 1.0));
  const double roll = std::atan2(rotation(2, 1), rotation(2, 2));
  const double yaw = std::atan2(rotation(1, 0), rotation(0, 0));
  return Eigen::Vector3d(roll, pitch, yaw);
}

Rigid3d VehicleFromCam(const World& world, const SurveyOptions& options) {
  return MakeVehicleFromCam(IsWallSurvey(world), options);
}

std::vector<SurveyStation> PlanSurvey(SurveyKind kind, const World& world,
                                      const Camera& camera,
                                      const SurveyOptions& options,
                                      uint64_t seed) {
  options.Check();
  const bool wall = IsWallSurvey(world);
  const Rigid3d vehicle_from_cam = VehicleFromCam(world, options);
  const Eigen::Vector3d normal = world.survey_normal.normalized();
  const Eigen::Vector3d along = world.survey_along.normalized();
  const Eigen::Vector3d across = normal.cross(along);
  const Eigen::Vector2d footprint = Footprint(camera, options.distance_m);
  // Down-looking: image x across track; side-looking: image x along track.
  const double footprint_along = wall ? footprint.x() : footprint.y();
  const double footprint_across = wall ? footprint.y() : footprint.x();

  const double half_along =
      0.5 * std::max(0.0, options.coverage_along * world.survey_length -
                              footprint_along);
  const double half_across =
      0.5 * std::max(0.0, options.coverage_across * world.survey_width -
                              footprint_across);
  const std::vector<double> stations_along =
      Spread(half_along, footprint_along * (1.0 - options.forward_overlap));
  std::vector<double> passes = {0.0};
  if (kind == SurveyKind::kLawnmower) {
    passes =
        Spread(half_across, footprint_across * (1.0 - options.side_overlap));
  }

  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal01(0.0, 1.0);
  const double attitude_sigma = options.attitude_jitter_deg * kDegToRad;
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();

  std::vector<SurveyStation> stations;
  double time = 0.0;
  Eigen::Vector3d previous_position = Eigen::Vector3d::Zero();
  for (size_t p = 0; p < passes.size(); ++p) {
    // A wall is always imaged on the starboard side, so every pass runs in
    // the same direction; a floor is mown back and forth.
    Eigen::Vector3d travel = wall ? up.cross(-normal).normalized() : along;
    if (!wall && p % 2 == 1) travel = -travel;
    const bool reversed = travel.dot(along) < 0.0;
    for (size_t s = 0; s < stations_along.size(); ++s) {
      if (options.max_images > 0 &&
          static_cast<int>(stations.size()) >= options.max_images) {
        return stations;
      }
      const double position_along =
          stations_along[reversed ? stations_along.size() - 1 - s : s];
      const Eigen::Vector3d camera_centre =
          world.survey_origin + position_along * along + passes[p] * across +
          options.distance_m * normal;
      Eigen::Vector3d rpy(0.0, 0.0, std::atan2(travel.y(), travel.x()));
      rpy += attitude_sigma *
             Eigen::Vector3d(normal01(rng), normal01(rng), normal01(rng));
      const Eigen::Matrix3d world_from_vehicle = WorldFromVehicleRotation(rpy);
      Eigen::Vector3d vehicle_position =
          camera_centre - world_from_vehicle * vehicle_from_cam.translation;
      vehicle_position +=
          options.position_jitter_m *
          Eigen::Vector3d(normal01(rng), normal01(rng), normal01(rng));
      if (!stations.empty()) {
        time += (vehicle_position - previous_position).norm() /
                options.speed_m_per_s;
      }
      previous_position = vehicle_position;

      SurveyStation station;
      std::ostringstream name;
      name << std::setw(5) << std::setfill('0') << stations.size();
      station.image_name = name.str();
      station.time_s = time;
      station.pass = static_cast<int>(p);
      station.vehicle_rpy = rpy;
      station.vehicle_position = vehicle_position;
      Rigid3d world_from_vehicle_pose;
      world_from_vehicle_pose.rotation = Eigen::Quaterniond(world_from_vehicle);
      world_from_vehicle_pose.translation = vehicle_position;
      Rigid3d world_from_cam;
      world_from_cam.rotation =
          world_from_vehicle_pose.rotation * vehicle_from_cam.rotation;
      world_from_cam.translation =
          world_from_vehicle * vehicle_from_cam.translation + vehicle_position;
      station.cam_from_world = world_from_cam.Inverse();
      stations.push_back(station);
    }
  }
  return stations;
}

}  // namespace uw::sim
