#include "sim/generate.h"

#include <algorithm>
#include <memory>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>

#include "colmap_plugins/scene/model_io.h"
#include "common/mesh/mesh.h"
#include "common/mesh/ray_caster.h"
#include "common/util/error.h"
#include "common/util/exif_time.h"
#include "common/util/file.h"
#include "common/util/json_fields.h"
#include "laserscale/laser_setup.h"
#include "sim/distractors.h"
#include "sim/laser_images.h"
#include "sim/logs.h"
#include "sim/rig.h"

namespace uw::sim {
namespace {

namespace fs = std::filesystem;

PendingFile TextFile(const fs::path& path, std::string content) {
  return {path, [content = std::move(content)](std::ostream& stream) {
            stream << content;
          }};
}

std::string RefImagesText(const std::vector<SurveyStation>& stations) {
  std::string text;
  for (const SurveyStation& station : stations) {
    const Eigen::Vector3d centre = station.cam_from_world.Inverse().translation;
    text += fmt::format("{} {:.17g} {:.17g} {:.17g}\n", station.image_name,
                        centre.x(), centre.y(), centre.z());
  }
  return text;
}

// image_name,time rows on the logs' clock; `what` names the images in the
// comment line.
std::string TimesCsv(
    const std::string& what,
    const std::vector<std::pair<std::string, double>>& name_times,
    const std::optional<double>& clock_start_s) {
  std::string text = fmt::format("# uwsim {} times: {}\nimage_name,time\n",
                                 what, LogTimeUnits(clock_start_s));
  for (const auto& [name, time_s] : name_times) {
    text += fmt::format("{},{:.17g}\n", name, LogTime(clock_start_s, time_s));
  }
  return text;
}

std::string ImageTimesCsv(const std::vector<SurveyStation>& stations,
                          const std::optional<double>& clock_start_s) {
  std::vector<std::pair<std::string, double>> name_times;
  for (const SurveyStation& station : stations) {
    name_times.emplace_back(station.image_name, station.time_s);
  }
  return TimesCsv("image", name_times, clock_start_s);
}

// A user knows when each laser image was taken (its file's time stamp), so
// that the navigation can place it before it is matched (add_laser_images.sh).
std::string LaserImageTimesCsv(const std::vector<LaserShot>& shots,
                               const std::optional<double>& clock_start_s) {
  std::vector<std::pair<std::string, double>> name_times;
  for (const LaserShot& shot : shots) {
    name_times.emplace_back(shot.name, shot.time_s);
  }
  return TimesCsv("laser image", name_times, clock_start_s);
}

// Camera k's images are images[k]; cameras[k] gets camera_id k + 1.
Reconstruction TrueModel(
    const std::vector<Camera>& cameras,
    const std::vector<std::vector<SurveyStation>>& images) {
  Reconstruction model;
  image_t image_id = 0;
  for (size_t k = 0; k < cameras.size(); ++k) {
    Camera camera = cameras[k];
    camera.camera_id = static_cast<camera_t>(k + 1);
    model.AddCamera(camera);
    for (const SurveyStation& station : images[k]) {
      Image image;
      image.image_id = ++image_id;
      image.camera_id = camera.camera_id;
      image.name = station.image_name;
      image.cam_from_world = station.cam_from_world;
      model.AddImage(image);
    }
  }
  return model;
}

}  // namespace

GenerateSummary Generate(const SimConfig& config, const fs::path& out,
                         const std::function<void(size_t, size_t)>& progress,
                         bool render_images) {
  config.Check();
  if (fs::exists(out) && !fs::is_empty(out)) {
    throw ErrorAt(out.string(),
                  ": output folder exists and is not empty; choose a new one");
  }
  World world = MakeWorld(config.world, config.world_options, config.seed);
  size_t num_distractors = 0;
  if (config.distractors.Any()) {
    std::vector<Distractor> distractors =
        ScatterDistractors(world.mesh, config.distractors, config.seed);
    num_distractors = distractors.size();
    world.texture = std::make_shared<DistractorTexture>(
        std::move(world.texture), std::move(distractors));
  }
  std::vector<SurveyStation> stations = PlanSurvey(
      config.survey, world, config.camera, config.survey_options, config.seed);
  if (stations.empty()) throw ErrorAt("the survey has no images");
  const std::string extension =
      config.render.sensor.jpeg_quality > 0 ? ".jpg" : ".png";
  // With a rig, camera k's images go to images/camk/.
  const bool rig = !config.rig.cameras.empty();
  for (SurveyStation& station : stations) {
    station.image_name = (rig ? "cam1/" : "") + station.image_name + extension;
  }
  std::vector<Camera> cameras = {config.camera};
  std::vector<std::vector<SurveyStation>> images = {stations};
  const Rigid3d vehicle_from_rig = VehicleFromCam(world, config.survey_options);
  for (size_t k = 0; k < config.rig.cameras.size(); ++k) {
    const RigCameraOptions& rig_camera = config.rig.cameras[k];
    cameras.push_back(rig_camera.camera);
    images.emplace_back();
    for (size_t i = 0; i < stations.size(); ++i) {
      SurveyStation station =
          StationOfRigCamera(stations, i, vehicle_from_rig,
                             rig_camera.cam_from_rig, rig_camera.time_offset_s);
      station.image_name =
          "cam" + std::to_string(k + 2) + stations[i].image_name.substr(4);
      images.back().push_back(station);
    }
  }
  std::vector<SurveyStation> all_images;
  for (const std::vector<SurveyStation>& camera_images : images) {
    all_images.insert(all_images.end(), camera_images.begin(),
                      camera_images.end());
  }

  GenerateSummary summary;
  summary.num_images = all_images.size();
  summary.num_triangles = world.mesh.triangles.size();
  // The navigation log samples the vehicle when the reference camera fires.
  const std::vector<NavigationRecord> navigation = NoisyNavigation(
      stations, config.navigation, config.seed, &summary.dive_biases);

  const RayCaster caster(world.mesh);
  // One renderer per camera: it unprojects every pixel once.
  // None without images: the loops below then render nothing.
  std::vector<std::unique_ptr<Renderer>> renderers;
  for (size_t k = 0; render_images && k < cameras.size(); ++k) {
    renderers.push_back(std::make_unique<Renderer>(caster, *world.texture,
                                                   cameras[k], config.render));
  }
  const std::vector<LaserShot> shots =
      PlanLaserShots(stations, config.lasers, config.seed);
  summary.num_laser_images = shots.size();
  const size_t num_frames =
      render_images ? all_images.size() + 2 * shots.size() : 0;
  size_t frames_done = 0;
  const bool jpeg = config.render.sensor.jpeg_quality > 0;
  // Frame k of the survey (laser images after the survey images) keys its
  // noise with index k.
  const std::optional<double> clock = config.logs.ClockStart();
  const auto render =
      [&](const Renderer& renderer, const Rigid3d& cam_from_world,
          const FrameOptions& frame, double time_s, const fs::path& path) {
        const RenderedImage rendered =
            renderer.Render(cam_from_world, config.seed, frames_done, frame);
        // With JPEG the file is the very encoding the renderer decoded, so the
        // image on disk is the one the noise model describes.
        std::vector<uchar> bytes = rendered.jpeg;
        if (!jpeg && !cv::imencode(".png", rendered.image, bytes)) {
          throw ErrorAt("cannot encode image ", path.string());
        }
        if (config.logs.exif_times) {
          bytes = WithExifCaptureTime(bytes, LogTime(clock, time_s),
                                      config.logs.CameraZoneOffset());
        }
        WriteFilesAtomically(
            {{path,
              [&bytes](std::ostream& stream) {
                stream.write(reinterpret_cast<const char*>(bytes.data()),
                             bytes.size());
              }}},
            true);
        ++frames_done;
        if (progress) progress(frames_done, num_frames);
      };
  for (size_t k = 0; k < renderers.size(); ++k) {
    for (const SurveyStation& station : images[k]) {
      render(*renderers[k], station.cam_from_world, FrameOptions(),
             station.time_s, out / "images" / station.image_name);
    }
  }

  const LaserSetup true_lasers = TrueLaserSetup(config.lasers);
  FrameOptions lasers_on;
  for (const Laser& laser : true_lasers.lasers) {
    const std::vector<std::string>& off = config.lasers.switched_off;
    if (std::find(off.begin(), off.end(), laser.name) == off.end()) {
      lasers_on.lasers.push_back(laser);
    }
  }
  lasers_on.optics = config.lasers.optics;
  FrameOptions aux_frame;
  aux_frame.gain_factor = config.lasers.aux_gain;
  if (config.lasers.auxiliary == "shifted") {
    aux_frame.lasers = lasers_on.lasers;
    aux_frame.optics = lasers_on.optics;
  }
  nlohmann::json shots_truth = nlohmann::json::array();
  for (const LaserShot& shot : shots) {
    if (render_images) {
      render(*renderers[0], shot.cam_from_world, lasers_on, shot.time_s,
             out / "laser_images" / shot.name);
      render(*renderers[0], shot.aux_cam_from_world, aux_frame, shot.time_s,
             out / "laser_images" / shot.aux_name);
    }
    shots_truth.push_back(LaserShotTruth(shot, true_lasers, config.lasers,
                                         caster, config.camera));
  }
  const nlohmann::json laser_images_json = {
      {"format", "uwmetric-sim-laser-images"},
      {"version", 1},
      {"setup", true_lasers.name},
      {"camera_id", 1},
      {"images", shots_truth}};

  nlohmann::json sim_json = config;
  sim_json["truth"] = {
      {"camera_mount", CameraMountName(SurveyCameraMount(world))},
      {"visible_range_m", VisibleRange(config.render)},
      {"rendered", render_images},
      {"dive_biases_m", ToJson(summary.dive_biases)},
      {"num_images", all_images.size()},
      {"num_laser_images", shots.size()},
      {"num_distractors", num_distractors},
      {"num_triangles", summary.num_triangles}};
  WriteModel(TrueModel(cameras, images), out / "truth", ModelFormat::kText);
  WritePly(world.mesh, out / "truth" / "mesh.ply",
           "uwsim world mesh; units: metres, world frame x east, y north, z "
           "up");
  // The logs on their clock.
  std::vector<NavigationRecord> logged = navigation;
  std::vector<NavigationRecord> true_logged = TrueNavigation(stations);
  for (std::vector<NavigationRecord>* records : {&logged, &true_logged}) {
    for (NavigationRecord& record : *records) {
      record.time_s = LogTime(clock, record.time_s);
    }
  }
  const double site_depth_m = config.navigation.site_depth_m;
  std::vector<PendingFile> files = {
      TextFile(out / "image_times.csv", ImageTimesCsv(all_images, clock)),
      TextFile(out / "laser_image_times.csv", LaserImageTimesCsv(shots, clock)),
      TextFile(out / "nav.csv",
               NavigationCsv(logged, site_depth_m, LogTimeUnits(clock))),
      TextFile(out / "truth" / "nav.csv",
               NavigationCsv(true_logged, site_depth_m, LogTimeUnits(clock))),
      TextFile(out / "truth" / "ref_images.txt", RefImagesText(all_images)),
      TextFile(out / "lasers.json",
               LasersJsonText({CalibratedLaserSetup(true_lasers, config.lasers,
                                                    config.seed)})),
      TextFile(out / "truth" / "lasers.json", LasersJsonText({true_lasers})),
      TextFile(out / "truth" / "laser_images.json",
               laser_images_json.dump(2) + "\n"),
      TextFile(out / "truth" / "sim.json", sim_json.dump(2) + "\n")};
  if (!config.logs.nav_formats.empty()) {
    const LocalEnu local(config.logs.Origin(site_depth_m));
    for (const std::string& format : config.logs.nav_formats) {
      if (format == "nmea") {
        files.push_back(
            TextFile(out / "nav.nmea", NmeaNavigationLog(logged, local)));
      } else if (format == "waterlinked") {
        files.push_back(
            TextFile(out / "nav_waterlinked.csv",
                     WaterLinkedNavigationLog(
                         logged, local,
                         UgpsTopsideFromText(config.logs.ugps_topside,
                                             "logs.ugps_topside"))));
      } else {
        files.push_back(
            TextFile(out / ("nav_" + format + ".csv"),
                     GeographicNavigationCsv(logged, local, format == "utm")));
      }
    }
  }
  if (rig) {
    files.push_back(
        TextFile(out / "rig.json", RigJsonText(config.rig, true, config.seed)));
    files.push_back(TextFile(out / "truth" / "rig.json",
                             RigJsonText(config.rig, false, config.seed)));
  }
  WriteFilesAtomically(files, false);
  return summary;
}

}  // namespace uw::sim
