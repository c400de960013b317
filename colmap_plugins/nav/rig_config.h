// rig.json, a camera rig's calibration (format "uwmetric-rig" version 1,
// docs/formats.md): per camera its COLMAP camera id, the folder prefix of
// its images, cam_from_rig with the standard deviations of that relative
// pose, and how long after the reference camera it fires. The rig frame is
// the reference (first) camera's.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "colmap_plugins/scene/model.h"

namespace uw {

struct RigCameraConfig {
  camera_t camera_id = 0;
  std::string image_prefix;  // e.g. "cam2/": the images whose names start so
  Rigid3d cam_from_rig;
  // 1-σ per axis of cam_from_rig's rotation (deg) and translation (m).
  double rotation_sigma_deg = 0.0;
  double translation_sigma_m = 0.0;
  double time_offset_s = 0.0;  // fires this long after the reference camera
};

struct RigConfig {
  std::vector<RigCameraConfig> cameras;  // cameras[0]: the reference

  // Throws uw::Error unless there is at least one camera; camera ids are
  // >= 1 and unique; prefixes are non-empty and none starts another (so an
  // image belongs to one camera at most); rotations are unit quaternions
  // (to 1e-6) and every value is finite, sigmas >= 0; and the reference
  // camera has the identity pose, no time offset and zero sigmas.
  void Check() const;
  // The camera whose image_prefix starts `image_name`, or nullptr.
  const RigCameraConfig* CameraOfImage(const std::string& image_name) const;
};

// A pose as JSON: {"qvec": [w, x, y, z], "tvec": [x, y, z]} (COLMAP's
// order). The writer normalises the quaternion; the reader takes it as it
// is, after checking it has 4 numbers of norm > 0.5.
nlohmann::json PoseJson(const Rigid3d& b_from_a);
Rigid3d PoseFromJson(const nlohmann::json& json, const std::string& where);

// Reads and checks rig.json; unknown keys are errors. Throws uw::Error
// naming the file and the key.
RigConfig ReadRigConfig(const std::filesystem::path& path);

// rig.json text (2-space indented JSON, keys sorted, newline at the end)
// of a checked rig.
std::string RigConfigJsonText(const RigConfig& rig);

}  // namespace uw
