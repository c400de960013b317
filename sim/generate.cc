#include "sim/generate.h"

#include <opencv2/imgcodecs.hpp>

#include "colmap_plugins/scene/model_io.h"
#include "colmap_plugins/util/error.h"
#include "colmap_plugins/util/file.h"
#include "sim/mesh.h"
#include "sim/ray_caster.h"

namespace uw::sim {
namespace {

namespace fs = std::filesystem;

PendingFile TextFile(const fs::path& path, std::string content) {
  return {path, [content = std::move(content)](std::ostream& stream) {
            stream << content;
          }};
}

std::string RefImagesText(const std::vector<SurveyStation>& stations) {
  std::ostringstream text;
  text.precision(17);
  for (const SurveyStation& station : stations) {
    const Eigen::Vector3d centre = station.cam_from_world.Inverse().translation;
    text << station.image_name << " " << centre.x() << " " << centre.y() << " "
         << centre.z() << "\n";
  }
  return text.str();
}

Reconstruction TrueModel(const SimConfig& config,
                         const std::vector<SurveyStation>& stations) {
  Reconstruction model;
  Camera camera = config.camera;
  camera.camera_id = 1;
  model.AddCamera(camera);
  for (size_t i = 0; i < stations.size(); ++i) {
    Image image;
    image.image_id = static_cast<image_t>(i + 1);
    image.camera_id = 1;
    image.name = stations[i].image_name;
    image.cam_from_world = stations[i].cam_from_world;
    model.AddImage(image);
  }
  return model;
}

}  // namespace

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
  render.Check();
}

void to_json(nlohmann::json& json, const SimConfig& config) {
  json = {{"world", WorldKindName(config.world)},
          {"survey", SurveyKindName(config.survey)},
          {"seed", config.seed},
          {"camera",
           {{"model", CameraModelIdToName(config.camera.model_id)},
            {"width", config.camera.width},
            {"height", config.camera.height},
            {"params", config.camera.params}}},
          {"world_options", config.world_options},
          {"survey_options", config.survey_options},
          {"navigation", config.navigation},
          {"render", config.render}};
}

void from_json(const nlohmann::json& json, SimConfig& config) {
  for (const auto& [key, value] : json.items()) {
    if (key == "world") {
      config.world = WorldKindFromName(value.get<std::string>());
    } else if (key == "survey") {
      config.survey = SurveyKindFromName(value.get<std::string>());
    } else if (key == "seed") {
      config.seed = value.get<uint64_t>();
    } else if (key == "camera") {
      const std::string model = value.at("model").get<std::string>();
      config.camera.model_id = CameraModelNameToId(model);
      if (config.camera.model_id == CameraModelId::kInvalid) {
        throw ErrorAt("unknown camera model '", model, "'");
      }
      config.camera.width = value.at("width").get<uint64_t>();
      config.camera.height = value.at("height").get<uint64_t>();
      config.camera.params = value.at("params").get<std::vector<double>>();
    } else if (key == "world_options") {
      value.get_to(config.world_options);
    } else if (key == "survey_options") {
      value.get_to(config.survey_options);
    } else if (key == "navigation") {
      value.get_to(config.navigation);
    } else if (key == "render") {
      value.get_to(config.render);
    } else {
      throw ErrorAt("unknown configuration section '", key, "'");
    }
  }
}

GenerateSummary Generate(const SimConfig& config, const fs::path& out,
                         const std::function<void(size_t, size_t)>& progress) {
  config.Check();
  if (fs::exists(out) && !fs::is_empty(out)) {
    throw ErrorAt(out.string(),
                  ": output folder exists and is not empty; choose a new one");
  }
  const World world =
      MakeWorld(config.world, config.world_options, config.seed);
  std::vector<SurveyStation> stations = PlanSurvey(
      config.survey, world, config.camera, config.survey_options, config.seed);
  if (stations.empty()) throw ErrorAt("the survey has no images");
  const std::string extension =
      config.render.sensor.jpeg_quality > 0 ? ".jpg" : ".png";
  for (SurveyStation& station : stations) station.image_name += extension;

  GenerateSummary summary;
  summary.num_images = stations.size();
  summary.num_triangles = world.mesh.triangles.size();
  const std::vector<NavigationRecord> navigation = NoisyNavigation(
      stations, config.navigation, config.seed, &summary.dive_biases);

  const RayCaster caster(world.mesh);
  // One renderer for the survey: it unprojects every pixel once.
  const Renderer renderer(caster, *world.texture, config.camera, config.render);
  const bool jpeg = config.render.sensor.jpeg_quality > 0;
  for (size_t i = 0; i < stations.size(); ++i) {
    const RenderedImage rendered =
        renderer.Render(stations[i].cam_from_world, config.seed, i);
    // With JPEG the file is the very encoding the renderer decoded, so the
    // image on disk is the one the noise model describes.
    std::vector<uchar> bytes = rendered.jpeg;
    if (!jpeg && !cv::imencode(".png", rendered.image, bytes)) {
      throw ErrorAt("cannot encode image ", stations[i].image_name);
    }
    WriteFilesAtomically({{out / "images" / stations[i].image_name,
                           [&bytes](std::ostream& stream) {
                             stream.write(
                                 reinterpret_cast<const char*>(bytes.data()),
                                 bytes.size());
                           }}},
                         true);
    if (progress) progress(i + 1, stations.size());
  }

  nlohmann::json sim_json = config;
  nlohmann::json biases = nlohmann::json::array();
  for (const Eigen::Vector3d& bias : summary.dive_biases) {
    biases.push_back({bias.x(), bias.y(), bias.z()});
  }
  sim_json["truth"] = {{"dive_biases_m", biases},
                       {"num_images", stations.size()},
                       {"num_triangles", summary.num_triangles}};
  WriteModel(TrueModel(config, stations), out / "truth", ModelFormat::kText);
  WritePly(world.mesh, out / "truth" / "mesh.ply");
  WriteFilesAtomically(
      {TextFile(out / "nav.csv",
                NavigationCsv(navigation, config.navigation.site_depth_m)),
       TextFile(out / "truth" / "nav.csv",
                NavigationCsv(TrueNavigation(stations),
                              config.navigation.site_depth_m)),
       TextFile(out / "truth" / "ref_images.txt", RefImagesText(stations)),
       TextFile(out / "truth" / "sim.json", sim_json.dump(2) + "\n")},
      false);
  return summary;
}

}  // namespace uw::sim
