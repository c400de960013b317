// Camera rigs in uwsim: several cameras on the vehicle with fixed relative
// poses, each firing with its own time offset (unsynchronized), and the
// rig.json that describes them (docs/formats.md).
//
// The rig frame is the reference camera's (SimConfig::camera, camera_id 1,
// time offset 0). Between survey stations the vehicle moves along straight
// lines with its attitude slerped, so a camera firing dt after a station
// sees the world from the vehicle pose interpolated (or, past the last
// station of a line, extrapolated) at that time.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "colmap_plugins/nav/rig_config.h"  // PoseJson, PoseFromJson
#include "colmap_plugins/scene/model.h"
#include "sim/survey.h"

namespace uw::sim {

// A COLMAP camera as JSON: {"model", "width", "height", "params"}.
nlohmann::json CameraJson(const Camera& camera);
Camera CameraFromJson(const nlohmann::json& json, const std::string& where);

struct RigCameraOptions {
  Camera camera;
  Rigid3d cam_from_rig;
  double time_offset_s = 0.0;  // fires this long after the reference camera
};

struct RigOptions {
  // The cameras besides the reference one; none: no rig.
  std::vector<RigCameraOptions> cameras;
  // Standard deviations of the relative poses written to OUT/rig.json (the
  // calibration a user would have; truth/rig.json has the exact ones).
  double rotation_sigma_deg = 0.05;
  double translation_sigma_m = 0.002;

  void Check() const;
};
void to_json(nlohmann::json& json, const RigOptions& options);
void from_json(const nlohmann::json& json, RigOptions& options);

// The station of the survey as camera `cam_from_rig` firing `time_offset_s`
// after station `index`: its vehicle pose moved along the line (same dive
// and pass) and the camera pose from `vehicle_from_rig`.
SurveyStation StationOfRigCamera(const std::vector<SurveyStation>& stations,
                                 size_t index, const Rigid3d& vehicle_from_rig,
                                 const Rigid3d& cam_from_rig,
                                 double time_offset_s);

// rig.json (colmap_plugins/nav/rig_config.h): the reference camera (id 1,
// images cam1/) then the others (ids 2, 3, ..., images cam2/, ...). With
// `perturb`, the relative poses of the non-reference cameras are perturbed
// by the sigmas (drawn from `seed`), which rig.json then reports.
std::string RigJsonText(const RigOptions& options, bool perturb, uint64_t seed);

}  // namespace uw::sim
