#include "colmap_plugins/nav/rig_config.h"

#include <cmath>
#include <cstdint>
#include <limits>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "common/util/error.h"
#include "common/util/file.h"
#include "common/util/json_fields.h"

namespace uw {
namespace {

constexpr char kFormat[] = "uwmetric-rig";
constexpr int kVersion = 1;
constexpr char kFrame[] =
    "rig = camera 1 (COLMAP camera frame); cam_from_rig maps rig "
    "coordinates to each camera's";

bool StartsWith(const std::string& text, const std::string& prefix) {
  return text.compare(0, prefix.size(), prefix) == 0;
}

void CheckCamera(const RigCameraConfig& camera, const std::string& where) {
  if (camera.camera_id == 0 ||
      camera.camera_id >=
          static_cast<camera_t>(std::numeric_limits<int32_t>::max())) {
    throw ErrorAt(where, ".camera_id = ", camera.camera_id,
                  ": must be a COLMAP camera id >= 1");
  }
  if (camera.image_prefix.empty()) {
    throw ErrorAt(where, ".image_prefix: must not be empty");
  }
  const double norm = camera.cam_from_rig.rotation.norm();
  if (!(std::abs(norm - 1.0) <= 1e-6)) {
    throw ErrorAt(where, ".cam_from_rig.qvec: norm ", norm,
                  " is not 1 (a unit quaternion w, x, y, z to 1e-6)");
  }
  if (!camera.cam_from_rig.translation.allFinite()) {
    throw ErrorAt(where, ".cam_from_rig.tvec: must be finite");
  }
  const auto check_sigma = [&](double value, const char* key) {
    if (!(std::isfinite(value) && value >= 0.0)) {
      throw ErrorAt(where, ".", key, " = ", value, ": must be finite and >= 0");
    }
  };
  check_sigma(camera.rotation_sigma_deg, "rotation_sigma_deg");
  check_sigma(camera.translation_sigma_m, "translation_sigma_m");
  if (!std::isfinite(camera.time_offset_s)) {
    throw ErrorAt(where, ".time_offset_s: must be finite");
  }
}

void CheckRig(const RigConfig& rig, const std::string& where) {
  if (rig.cameras.empty()) throw ErrorAt(where, ": no cameras");
  for (size_t i = 0; i < rig.cameras.size(); ++i) {
    const RigCameraConfig& camera = rig.cameras[i];
    const std::string camera_where =
        where + ": cameras[" + std::to_string(i) + "]";
    CheckCamera(camera, camera_where);
    for (size_t j = 0; j < i; ++j) {
      const RigCameraConfig& other = rig.cameras[j];
      if (other.camera_id == camera.camera_id) {
        throw ErrorAt(camera_where, ".camera_id = ", camera.camera_id,
                      ": cameras[", j, "] has the same id");
      }
      if (StartsWith(camera.image_prefix, other.image_prefix) ||
          StartsWith(other.image_prefix, camera.image_prefix)) {
        throw ErrorAt(camera_where, ".image_prefix '", camera.image_prefix,
                      "' and cameras[", j, "].image_prefix '",
                      other.image_prefix,
                      "': one starts the other, so an image would belong "
                      "to both");
      }
    }
  }
  const RigCameraConfig& reference = rig.cameras[0];
  const bool identity =
      reference.cam_from_rig.rotation.normalized().angularDistance(
          Eigen::Quaterniond::Identity()) <= 1e-12 &&
      reference.cam_from_rig.translation.norm() <= 1e-12;
  if (!identity || reference.time_offset_s != 0.0 ||
      reference.rotation_sigma_deg != 0.0 ||
      reference.translation_sigma_m != 0.0) {
    throw ErrorAt(where,
                  ": cameras[0] is the reference camera (the rig frame): "
                  "its cam_from_rig must be the identity (qvec [1, 0, 0, 0], "
                  "tvec [0, 0, 0]) and its time_offset_s and sigmas 0");
  }
}

// A COLMAP camera id: a JSON integer in [1, 2^31 - 1).
camera_t CameraId(const nlohmann::json& json, const std::string& where) {
  if (!json.is_number_integer() || json.get<int64_t>() < 1 ||
      json.get<int64_t>() >= std::numeric_limits<int32_t>::max()) {
    throw ErrorAt(where,
                  ".camera_id: expected a COLMAP camera id (an integer "
                  ">= 1), got ",
                  json.dump());
  }
  return static_cast<camera_t>(json.get<int64_t>());
}

}  // namespace

void RigConfig::Check() const { CheckRig(*this, "rig"); }

const RigCameraConfig* RigConfig::CameraOfImage(
    const std::string& image_name) const {
  for (const RigCameraConfig& camera : cameras) {
    if (StartsWith(image_name, camera.image_prefix)) return &camera;
  }
  return nullptr;
}

nlohmann::json PoseJson(const Rigid3d& b_from_a) {
  const Eigen::Quaterniond q = b_from_a.rotation.normalized();
  return {{"qvec", {q.w(), q.x(), q.y(), q.z()}},
          {"tvec", ToJson(b_from_a.translation)}};
}

Rigid3d PoseFromJson(const nlohmann::json& json, const std::string& where) {
  JsonFields fields(json, where);
  std::vector<double> qvec;
  Rigid3d pose;
  fields.Require("qvec", &qvec);
  fields.Require("tvec", &pose.translation);
  fields.RejectUnknown();
  if (qvec.size() != 4 || !(Eigen::Vector4d(qvec.data()).norm() > 0.5)) {
    throw ErrorAt(where,
                  ".qvec: expected 4 numbers (w, x, y, z) of a unit "
                  "quaternion");
  }
  pose.rotation = Eigen::Quaterniond(qvec[0], qvec[1], qvec[2], qvec[3]);
  return pose;
}

RigConfig ReadRigConfig(const std::filesystem::path& path) {
  const std::string where = path.string();
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(ReadFileToString(path));
  } catch (const nlohmann::json::parse_error& error) {
    throw ErrorAt(where, ": not valid JSON: ", error.what());
  }
  JsonFields fields(json, where);
  std::string format;
  int version = 0;
  std::string frame;
  nlohmann::json cameras;
  fields.Require("format", &format);
  fields.Require("version", &version);
  fields.Read("frame", &frame);
  fields.Require("cameras", &cameras);
  fields.RejectUnknown();
  if (format != kFormat || version != kVersion) {
    throw ErrorAt(where, ": format \"", format, "\" version ", version,
                  " is not \"", kFormat, "\" version ", kVersion);
  }
  if (!cameras.is_array()) {
    throw ErrorAt(where, ": cameras: expected an array, got ", cameras.dump());
  }
  RigConfig rig;
  for (size_t i = 0; i < cameras.size(); ++i) {
    const std::string camera_where =
        where + ": cameras[" + std::to_string(i) + "]";
    JsonFields camera_fields(cameras[i], camera_where);
    RigCameraConfig camera;
    nlohmann::json camera_id;
    nlohmann::json pose;
    camera_fields.Require("camera_id", &camera_id);
    camera_fields.Require("image_prefix", &camera.image_prefix);
    camera_fields.Require("cam_from_rig", &pose);
    camera_fields.Read("rotation_sigma_deg", &camera.rotation_sigma_deg);
    camera_fields.Read("translation_sigma_m", &camera.translation_sigma_m);
    camera_fields.Read("time_offset_s", &camera.time_offset_s);
    camera_fields.RejectUnknown();
    camera.camera_id = CameraId(camera_id, camera_where);
    camera.cam_from_rig = PoseFromJson(pose, camera_where + ".cam_from_rig");
    rig.cameras.push_back(camera);
  }
  CheckRig(rig, where);
  return rig;
}

std::string RigConfigJsonText(const RigConfig& rig) {
  rig.Check();
  nlohmann::json cameras = nlohmann::json::array();
  for (const RigCameraConfig& camera : rig.cameras) {
    cameras.push_back({{"camera_id", camera.camera_id},
                       {"image_prefix", camera.image_prefix},
                       {"cam_from_rig", PoseJson(camera.cam_from_rig)},
                       {"rotation_sigma_deg", camera.rotation_sigma_deg},
                       {"translation_sigma_m", camera.translation_sigma_m},
                       {"time_offset_s", camera.time_offset_s}});
  }
  const nlohmann::json json = {{"format", kFormat},
                               {"version", kVersion},
                               {"frame", kFrame},
                               {"cameras", cameras}};
  return json.dump(2) + "\n";
}

}  // namespace uw
