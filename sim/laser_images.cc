#include "sim/laser_images.h"

#include <algorithm>

#include <cmath>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "common/util/json_fields.h"
#include "common/util/random.h"
#include "sim/rig.h"

namespace uw::sim {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

// The pose halfway (in position and rotation) between two poses.
Rigid3d Halfway(const Rigid3d& a_from_world, const Rigid3d& b_from_world) {
  const Rigid3d world_from_a = a_from_world.Inverse();
  const Rigid3d world_from_b = b_from_world.Inverse();
  Rigid3d world_from_mid;
  world_from_mid.rotation = world_from_a.rotation.normalized().slerp(
      0.5, world_from_b.rotation.normalized());
  world_from_mid.translation =
      0.5 * (world_from_a.translation + world_from_b.translation);
  return world_from_mid.Inverse();
}

// A unit vector uniform on the sphere.
Eigen::Vector3d RandomDirection(SplitMix64Stream* random) {
  const double z = random->Uniform(-1.0, 1.0);
  const double angle = random->Uniform(0.0, 2.0 * M_PI);
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {r * std::cos(angle), r * std::sin(angle), z};
}

std::string AuxName(const std::string& name) {
  const size_t dot = name.rfind('.');
  if (dot == std::string::npos) return name + "_aux";
  return name.substr(0, dot) + "_aux" + name.substr(dot);
}

// "L" before the file name: "cam1/00002.png" -> "cam1/L00002.png".
std::string LaserName(const std::string& name) {
  const size_t slash = name.rfind('/');
  const size_t at = slash == std::string::npos ? 0 : slash + 1;
  return name.substr(0, at) + "L" + name.substr(at);
}

nlohmann::json SpotsJson(const LaserSetup& setup,
                         const std::vector<std::string>& switched_off,
                         const RayCaster& caster, const Camera& camera,
                         const Rigid3d& cam_from_world) {
  nlohmann::json spots = nlohmann::json::array();
  for (const Laser& laser : setup.lasers) {
    const LaserSpotTruth truth =
        TrueLaserSpot(caster, camera, cam_from_world, laser);
    const bool on = std::find(switched_off.begin(), switched_off.end(),
                              laser.name) == switched_off.end();
    nlohmann::json spot = {{"laser", laser.name},
                           {"on", on},
                           {"hit", truth.hit},
                           {"visible", truth.visible}};
    if (truth.hit) {
      spot["range_m"] = truth.range_m;
      spot["point_in_world"] = ToJson(truth.point_in_world);
    }
    if (truth.visible) spot["pixel"] = {truth.pixel.x(), truth.pixel.y()};
    spots.push_back(spot);
  }
  return spots;
}

}  // namespace

std::vector<LaserShot> PlanLaserShots(
    const std::vector<SurveyStation>& stations, const LaserOptions& options,
    uint64_t seed) {
  options.Check();
  std::vector<LaserShot> shots;
  if (options.every_nth_image == 0) return shots;
  const size_t every = static_cast<size_t>(options.every_nth_image);
  for (size_t i = every - 1; i < stations.size(); i += every) {
    const SurveyStation& station = stations[i];
    LaserShot shot;
    shot.name = LaserName(station.image_name);
    shot.aux_name = AuxName(shot.name);
    shot.survey_index = i;
    shot.dive = station.dive;
    shot.time_s = station.time_s;
    shot.cam_from_world = station.cam_from_world;
    if (options.placement == "between") {
      const auto same_line = [&](size_t j) {
        return stations[j].pass == station.pass &&
               stations[j].dive == station.dive;
      };
      const SurveyStation* other = nullptr;
      if (i + 1 < stations.size() && same_line(i + 1)) {
        other = &stations[i + 1];
      } else if (i > 0 && same_line(i - 1)) {
        other = &stations[i - 1];
      }
      if (other != nullptr) {
        shot.cam_from_world =
            Halfway(station.cam_from_world, other->cam_from_world);
        shot.time_s = 0.5 * (station.time_s + other->time_s);
      }
    }
    // The auxiliary image: a small motion of the camera, in its own frame.
    SplitMix64Stream random(
        SplitMix64(SplitMix64(seed) ^ (0xA0C5ull << 32) ^ i));
    Rigid3d aux_from_cam;
    aux_from_cam.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(
        options.aux_rotation_deg * kDegToRad, RandomDirection(&random)));
    aux_from_cam.translation =
        options.aux_translation_m * RandomDirection(&random);
    shot.aux_cam_from_world.rotation =
        aux_from_cam.rotation * shot.cam_from_world.rotation.normalized();
    shot.aux_cam_from_world.translation =
        aux_from_cam.rotation * shot.cam_from_world.translation +
        aux_from_cam.translation;
    shots.push_back(shot);
  }
  return shots;
}

nlohmann::json LaserShotTruth(const LaserShot& shot, const LaserSetup& setup,
                              const LaserOptions& options,
                              const RayCaster& caster, const Camera& camera) {
  const bool aux_lasers = options.auxiliary == "shifted";
  nlohmann::json json = {
      {"name", shot.name},
      {"survey_image_index", shot.survey_index},
      {"time", shot.time_s},
      {"dive", shot.dive},
      {"cam_from_world", PoseJson(shot.cam_from_world)},
      {"spots", SpotsJson(setup, options.switched_off, caster, camera,
                          shot.cam_from_world)},
      {"aux",
       {{"name", shot.aux_name},
        {"cam_from_world", PoseJson(shot.aux_cam_from_world)},
        {"gain_factor", options.aux_gain},
        {"lasers_on", aux_lasers}}}};
  if (aux_lasers) {
    json["aux"]["spots"] = SpotsJson(setup, options.switched_off, caster,
                                     camera, shot.aux_cam_from_world);
  }
  return json;
}

}  // namespace uw::sim
