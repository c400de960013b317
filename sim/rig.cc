#include "sim/rig.h"

#include <cmath>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "common/util/error.h"
#include "common/util/json_fields.h"
#include "common/util/random.h"

namespace uw::sim {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

// The image folder of camera `index` (0: the reference) in a rig.
std::string Prefix(size_t index) {
  return "cam" + std::to_string(index + 1) + "/";
}

}  // namespace

nlohmann::json CameraJson(const Camera& camera) {
  return {{"model", CameraModelIdToName(camera.model_id)},
          {"width", camera.width},
          {"height", camera.height},
          {"params", camera.params}};
}

Camera CameraFromJson(const nlohmann::json& json, const std::string& where) {
  JsonFields fields(json, where);
  std::string model;
  Camera camera;
  fields.Require("model", &model);
  fields.Require("width", &camera.width);
  fields.Require("height", &camera.height);
  fields.Require("params", &camera.params);
  fields.RejectUnknown();
  camera.model_id = CameraModelNameToId(model);
  if (camera.model_id == CameraModelId::kInvalid) {
    throw ErrorAt(where, ": unknown camera model '", model, "'");
  }
  return camera;
}

void RigOptions::Check() const {
  for (size_t i = 0; i < cameras.size(); ++i) {
    const RigCameraOptions& rig_camera = cameras[i];
    const std::string where = "rig.cameras[" + std::to_string(i) + "]";
    CheckCameraModelParams(rig_camera.camera.model_id,
                           rig_camera.camera.params.size());
    if (rig_camera.camera.width == 0 || rig_camera.camera.height == 0) {
      throw ErrorAt(where, ": camera size must be positive");
    }
    if (!rig_camera.cam_from_rig.translation.allFinite() ||
        std::abs(rig_camera.cam_from_rig.rotation.norm() - 1.0) > 1e-6) {
      throw ErrorAt(where,
                    ": cam_from_rig must have a unit quaternion and a "
                    "finite translation");
    }
    if (!(std::abs(rig_camera.time_offset_s) <= 10.0)) {
      throw ErrorAt(where, ": time_offset_s = ", rig_camera.time_offset_s,
                    " must be within +-10 s");
    }
  }
  if (!(rotation_sigma_deg >= 0.0 && rotation_sigma_deg <= 5.0 &&
        translation_sigma_m >= 0.0 && translation_sigma_m <= 0.1)) {
    throw ErrorAt(
        "rig: rotation_sigma_deg must be in [0, 5] and "
        "translation_sigma_m in [0, 0.1]");
  }
}

void to_json(nlohmann::json& json, const RigOptions& options) {
  nlohmann::json cameras = nlohmann::json::array();
  for (const RigCameraOptions& rig_camera : options.cameras) {
    cameras.push_back({{"camera", CameraJson(rig_camera.camera)},
                       {"cam_from_rig", PoseJson(rig_camera.cam_from_rig)},
                       {"time_offset_s", rig_camera.time_offset_s}});
  }
  json = {{"cameras", cameras},
          {"rotation_sigma_deg", options.rotation_sigma_deg},
          {"translation_sigma_m", options.translation_sigma_m}};
}

void from_json(const nlohmann::json& json, RigOptions& options) {
  JsonFields fields(json, "rig");
  nlohmann::json cameras;
  fields.Read("cameras", &cameras);
  fields.Read("rotation_sigma_deg", &options.rotation_sigma_deg);
  fields.Read("translation_sigma_m", &options.translation_sigma_m);
  fields.RejectUnknown();
  if (cameras.is_null()) return;
  if (!cameras.is_array()) throw ErrorAt("rig.cameras: expected an array");
  options.cameras.clear();
  for (size_t i = 0; i < cameras.size(); ++i) {
    const std::string where = "rig.cameras[" + std::to_string(i) + "]";
    JsonFields camera_fields(cameras[i], where);
    nlohmann::json camera;
    nlohmann::json pose;
    RigCameraOptions rig_camera;
    camera_fields.Require("camera", &camera);
    camera_fields.Require("cam_from_rig", &pose);
    camera_fields.Read("time_offset_s", &rig_camera.time_offset_s);
    camera_fields.RejectUnknown();
    rig_camera.camera = CameraFromJson(camera, where + ".camera");
    rig_camera.cam_from_rig = PoseFromJson(pose, where + ".cam_from_rig");
    options.cameras.push_back(rig_camera);
  }
}

SurveyStation StationOfRigCamera(const std::vector<SurveyStation>& stations,
                                 size_t index, const Rigid3d& vehicle_from_rig,
                                 const Rigid3d& cam_from_rig,
                                 double time_offset_s) {
  const SurveyStation& station = stations.at(index);
  // The segment of the line that brackets the time (or the nearest one).
  const auto same_line = [&](size_t j) {
    return stations[j].dive == station.dive && stations[j].pass == station.pass;
  };
  size_t from = index;
  size_t to = index;
  if (time_offset_s >= 0.0 && index + 1 < stations.size() &&
      same_line(index + 1)) {
    to = index + 1;
  } else if (index > 0 && same_line(index - 1)) {
    from = index - 1;
  } else if (index + 1 < stations.size() && same_line(index + 1)) {
    to = index + 1;
  }
  SurveyStation moved = station;
  moved.time_s = station.time_s + time_offset_s;
  if (from != to) {
    const SurveyStation& a = stations[from];
    const SurveyStation& b = stations[to];
    const double fraction = (moved.time_s - a.time_s) / (b.time_s - a.time_s);
    moved.vehicle_position =
        a.vehicle_position +
        fraction * (b.vehicle_position - a.vehicle_position);
    const Eigen::Quaterniond qa(WorldFromVehicleRotation(a.vehicle_rpy));
    const Eigen::Quaterniond qb(WorldFromVehicleRotation(b.vehicle_rpy));
    // slerp extrapolates too: qa (qa^-1 qb)^fraction.
    const Eigen::AngleAxisd step(qa.conjugate() * qb);
    const Eigen::Quaterniond rotation =
        qa * Eigen::Quaterniond(
                 Eigen::AngleAxisd(fraction * step.angle(), step.axis()));
    moved.vehicle_rpy = RollPitchYawFromRotation(rotation.toRotationMatrix());
  }
  Rigid3d world_from_vehicle;
  world_from_vehicle.rotation =
      Eigen::Quaterniond(WorldFromVehicleRotation(moved.vehicle_rpy));
  world_from_vehicle.translation = moved.vehicle_position;
  const Rigid3d vehicle_from_world = world_from_vehicle.Inverse();
  const Rigid3d rig_from_vehicle = vehicle_from_rig.Inverse();
  // cam_from_world = cam_from_rig * rig_from_vehicle * vehicle_from_world.
  const auto compose = [](const Rigid3d& c_from_b, const Rigid3d& b_from_a) {
    Rigid3d c_from_a;
    c_from_a.rotation =
        c_from_b.rotation.normalized() * b_from_a.rotation.normalized();
    c_from_a.translation = c_from_b * b_from_a.translation;
    return c_from_a;
  };
  moved.cam_from_world =
      compose(cam_from_rig, compose(rig_from_vehicle, vehicle_from_world));
  return moved;
}

std::string RigJsonText(const RigOptions& options, bool perturb,
                        uint64_t seed) {
  SplitMix64Stream random(SplitMix64(seed ^ 0x816A00000000ull));
  RigConfig rig;
  RigCameraConfig reference;
  reference.camera_id = 1;
  reference.image_prefix = Prefix(0);
  rig.cameras.push_back(reference);
  for (size_t i = 0; i < options.cameras.size(); ++i) {
    RigCameraConfig camera;
    camera.camera_id = static_cast<camera_t>(i + 2);
    camera.image_prefix = Prefix(i + 1);
    camera.cam_from_rig = options.cameras[i].cam_from_rig;
    camera.time_offset_s = options.cameras[i].time_offset_s;
    if (perturb) {
      const Eigen::Vector3d rotation_error =
          options.rotation_sigma_deg * kDegToRad *
          Eigen::Vector3d(random.Gaussian(), random.Gaussian(),
                          random.Gaussian());
      const Eigen::Vector3d translation_error =
          options.translation_sigma_m * Eigen::Vector3d(random.Gaussian(),
                                                        random.Gaussian(),
                                                        random.Gaussian());
      if (rotation_error.norm() > 0.0) {
        camera.cam_from_rig.rotation =
            Eigen::Quaterniond(Eigen::AngleAxisd(rotation_error.norm(),
                                                 rotation_error.normalized())) *
            camera.cam_from_rig.rotation.normalized();
      }
      camera.cam_from_rig.translation += translation_error;
      camera.rotation_sigma_deg = options.rotation_sigma_deg;
      camera.translation_sigma_m = options.translation_sigma_m;
    }
    rig.cameras.push_back(camera);
  }
  return RigConfigJsonText(rig);
}

}  // namespace uw::sim
