#include "sim/sim_config.h"

#include <cmath>

#include "common/util/error.h"
#include "common/util/file.h"
#include "common/util/json_fields.h"

namespace uw::sim {

Camera SimConfig::DefaultCamera() {
  Camera camera;
  camera.camera_id = 1;
  camera.model_id = CameraModelId::kSimpleRadial;
  camera.width = 1024;
  camera.height = 768;
  camera.params = {850.0, 512.0, 384.0, -0.04};
  return camera;
}

void SimConfig::Check() const {
  CheckCameraModelParams(camera.model_id, camera.params.size());
  if (camera.width == 0 || camera.height == 0 || camera.width > 20000 ||
      camera.height > 20000) {
    throw ErrorAt("camera size ", camera.width, " x ", camera.height,
                  " is out of range (1 to 20000 pixels)");
  }
  for (const double param : camera.params) {
    if (!std::isfinite(param))
      throw ErrorAt("camera parameters must be finite");
  }
  world_options.Check();
  survey_options.Check();
  navigation.Check();
  logs.Check();
  navigation.CheckNumDives(
      survey == SurveyKind::kMultiDive ? survey_options.num_dives : 1);
  render.Check();
  lasers.Check();
  rig.Check();
  distractors.Check();
}

void to_json(nlohmann::json& json, const SimConfig& config) {
  json = {{"world", WorldKindName(config.world)},
          {"survey", SurveyKindName(config.survey)},
          {"seed", config.seed},
          {"camera", CameraJson(config.camera)},
          {"rig", config.rig},
          {"world_options", config.world_options},
          {"survey_options", config.survey_options},
          {"navigation", config.navigation},
          {"logs", config.logs},
          {"render", config.render},
          {"lasers", config.lasers},
          {"distractors", config.distractors}};
}

void from_json(const nlohmann::json& json, SimConfig& config) {
  JsonFields fields(json, "configuration");
  std::string name;
  if (fields.Read("world", &name)) config.world = WorldKindFromName(name);
  if (fields.Read("survey", &name)) config.survey = SurveyKindFromName(name);
  fields.Read("seed", &config.seed);
  nlohmann::json camera;
  if (fields.Read("camera", &camera)) {
    config.camera = CameraFromJson(camera, "camera");
    config.camera.camera_id = 1;
  }
  fields.Read("rig", &config.rig);
  fields.Read("world_options", &config.world_options);
  fields.Read("survey_options", &config.survey_options);
  fields.Read("navigation", &config.navigation);
  fields.Read("logs", &config.logs);
  fields.Read("render", &config.render);
  fields.Read("lasers", &config.lasers);
  fields.Read("distractors", &config.distractors);
  fields.RejectUnknown();
}

SimConfig ReadSimConfig(const std::filesystem::path& path) {
  const std::string where = path.string();
  const nlohmann::json json = ParseJsonText(ReadFileToString(path), where);
  SimConfig config;
  try {
    json.get_to(config);
  } catch (const Error& error) {
    throw ErrorAt(where, ": ", error.what());
  } catch (const nlohmann::json::exception& error) {
    throw ErrorAt(where, ": ", error.what());
  }
  return config;
}

}  // namespace uw::sim
