#include "colmap_plugins/nav/pose_prior_import.h"

#include <algorithm>
#include <set>
#include <unordered_map>

#include <fmt/format.h>
#include <Eigen/Eigenvalues>

#include "colmap_plugins/nav/image_times.h"
#include "colmap_plugins/nav/nav_csv.h"
#include "colmap_plugins/nav/nav_plausibility.h"
#include "colmap_plugins/nav/rig_config.h"
#include "common/util/error.h"

namespace uw {
namespace {

bool IsPositiveDefinite(const Eigen::Matrix3d& covariance) {
  const Eigen::Vector3d eigenvalues =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance,
                                                     Eigen::EigenvaluesOnly)
          .eigenvalues();
  return eigenvalues.minCoeff() > 1e-12 * eigenvalues.maxCoeff();
}

std::string CameraIds(const std::vector<DatabaseCamera>& cameras) {
  std::string ids;
  for (const DatabaseCamera& camera : cameras) {
    ids += (ids.empty() ? "" : ", ") + std::to_string(camera.camera_id);
  }
  return ids.empty() ? "none" : ids;
}

}  // namespace

void PosePriorImportOptions::Check() const {
  if (nav_path.empty()) throw ErrorAt("no navigation file given");
  nav_to_camera.Check();
  log.Check();
}

PosePrior DatabasePosePrior(const CameraPrior& prior, uint32_t image_id) {
  PosePrior database_prior;
  database_prior.image_id = image_id;
  database_prior.position = prior.position;
  database_prior.coordinate_system = PosePriorCoordinateSystem::kCartesian;
  // A singular covariance (a zero sigma) cannot weight anything; COLMAP
  // would invert it. Stored as unknown instead.
  if (IsPositiveDefinite(prior.position_covariance)) {
    database_prior.position_covariance = prior.position_covariance;
  }
  // What the log did not have is not written: a rotation from a log
  // without attitude would be the mount alone, a lie COLMAP would use.
  if (prior.cam_from_world_rotation) {
    const Eigen::Quaterniond& q = *prior.cam_from_world_rotation;
    database_prior.cam_from_world_rotation_wxyz =
        Eigen::Vector4d(q.w(), q.x(), q.y(), q.z());
  }
  if (prior.gravity_in_cam)
    database_prior.gravity_in_cam = *prior.gravity_in_cam;
  return database_prior;
}

std::string WorldFrameText(const NavLogFrame& frame) {
  if (!frame.origin) {
    return "the log's x,y,z (m)";
  }
  std::string text =
      "local east-north-up (m) at " + GeoOriginText(*frame.origin) +
      " (lat,lon,height; read from " + frame.position_columns + ")";
  if (frame.origin_automatic) {
    text += fmt::format(
        "; automatic, the first position rounded: --origin {:.3f},{:.3f} gives "
        "later commands the same frame",
        frame.origin->lat_deg, frame.origin->lon_deg);
  }
  return text;
}

nlohmann::json WorldFrameJson(const NavLogFrame& frame) {
  nlohmann::json json = {{"format", "uwmetric-world-frame"},
                         {"version", 1},
                         {"description", WorldFrameText(frame)},
                         {"units", "m"},
                         {"read_from", frame.position_columns}};
  if (frame.origin) {
    json["axes"] = {"east", "north", "up"};
    json["origin"] = {{"lat_deg", frame.origin->lat_deg},
                      {"lon_deg", frame.origin->lon_deg},
                      {"height_m", frame.origin->height_m},
                      {"datum", "WGS84"}};
    json["origin_automatic"] = frame.origin_automatic;
  } else {
    json["axes"] = {"the log's x", "the log's y", "the log's z"};
    json["origin"] = nullptr;
  }
  return json;
}

LoadedCameraPriors LoadCameraPriors(
    const PosePriorImportOptions& options,
    const std::vector<std::pair<std::string, camera_t>>& images,
    const std::string& images_source) {
  options.Check();
  LoadedCameraPriors loaded;
  NavigationSources sources;
  sources.nav = options.nav_path.string();
  loaded.nav = ReadNavigationLog(options.nav_path, options.log, &loaded.frame);
  for (const std::string& note : loaded.frame.notes) {
    loaded.warnings.push_back(note);
  }
  const std::vector<NavRecord>& nav = loaded.nav;
  if (const auto warning =
          DegreesLikePositionsWarning(nav, options.nav_path.string())) {
    loaded.warnings.push_back(*warning);
  } else if (const auto speed = SpeedWarning(nav, options.nav_path.string())) {
    // Degrees crawl at micrometres per second too: said once, above.
    loaded.warnings.push_back(*speed);
  }
  std::vector<ImageTime> image_times;
  if (!options.image_times_path.empty()) {
    sources.image_times = options.image_times_path.string();
    image_times = ReadImageTimesCsv(options.image_times_path,
                                    options.log.time_zone_offset_s);
  }
  if (!options.rig_config_path.empty()) {
    loaded.rig = ReadRigConfig(options.rig_config_path);
  }
  const RigConfig& rig = loaded.rig;
  const bool has_rig = !rig.cameras.empty();

  std::unordered_map<std::string, camera_t> camera_of_name;
  std::vector<std::string> image_names;
  for (const auto& [name, camera_id] : images) {
    camera_of_name.emplace(name, camera_id);
    image_names.push_back(name);
  }
  const auto given = [&](const std::string& name) {
    return camera_of_name.count(name) != 0;
  };
  // None of the `num_rows` rows of `file` (image_times.csv, or nav.csv)
  // names a given image.
  const auto none_given = [&](size_t num_rows, const std::string& file) {
    return ErrorAt(file, ": none of its ", num_rows, " rows names an image of ",
                   images_source, " (", images.size(),
                   " images): a log of another survey, or image names spelt "
                   "otherwise?");
  };
  const std::vector<ImageTime>* times = nullptr;
  if (!options.image_times_path.empty()) {
    // Left out before placing: an image the mapper dropped may have been
    // taken outside the navigation's span.
    std::vector<ImageTime> kept;
    for (const ImageTime& time : image_times) {
      if (given(time.image_name)) {
        kept.push_back(time);
      } else {
        loaded.other_images.push_back(time.image_name);
      }
    }
    if (kept.empty()) {
      throw none_given(image_times.size(), sources.image_times);
    }
    image_times = std::move(kept);
    times = &image_times;
  } else {
    if (nav.front().image_name.empty()) {
      throw ErrorAt(sources.nav, ":", nav.front().line,
                    ": the navigation has no image names; give the images' "
                    "times (--image_times)");
    }
    if (has_rig) {
      // The log samples the reference camera; the others fire with the
      // rig's delays after it. A row places the given images of its
      // station, its own image registered or not; a row that places none
      // is left out.
      image_times = RigImageTimes(nav, rig, image_names);
      sources.image_times = sources.nav;
      times = &image_times;
      std::set<int> used_lines;
      for (const ImageTime& time : image_times) used_lines.insert(time.line);
      for (const NavRecord& row : nav) {
        if (used_lines.count(row.line) == 0) {
          loaded.other_images.push_back(row.image_name);
        }
      }
    } else {
      for (const NavRecord& row : nav) {
        if (!given(row.image_name)) {
          loaded.other_images.push_back(row.image_name);
        }
      }
    }
    if (loaded.other_images.size() == nav.size()) {
      throw none_given(nav.size(), sources.nav);
    }
  }
  if (has_rig && times != nullptr) {
    for (const ImageTime& time : *times) {
      const RigCameraConfig* camera = rig.CameraOfImage(time.image_name);
      const camera_t camera_id = camera_of_name.at(time.image_name);
      if (camera != nullptr && camera->camera_id != camera_id) {
        throw ErrorAt(sources.image_times, ":", time.line, ": image '",
                      time.image_name, "' has camera ", camera_id, " in ",
                      images_source, ", but its prefix '", camera->image_prefix,
                      "' is camera ", camera->camera_id, " in ",
                      options.rig_config_path.string());
      }
    }
  }
  loaded.priors = CameraPriorsFromNavigation(nav, times, options.nav_to_camera,
                                             has_rig ? &rig : nullptr, sources);
  // Without image times each row is its image's prior, placed at its own
  // time whatever the image; the rows of other images go now.
  loaded.priors.erase(std::remove_if(loaded.priors.begin(), loaded.priors.end(),
                                     [&](const CameraPrior& prior) {
                                       return !given(prior.image_name);
                                     }),
                      loaded.priors.end());
  return loaded;
}

PosePriorImportSummary ImportPosePriors(
    const std::filesystem::path& database_path,
    const PosePriorImportOptions& options) {
  options.Check();
  Database database = Database::Open(database_path, Database::Mode::kReadWrite);
  const std::string database_name = database_path.string();
  std::unordered_map<std::string, DatabaseImage> image_of_name;
  std::vector<std::pair<std::string, camera_t>> images;
  for (const DatabaseImage& image : database.ReadAllImages()) {
    image_of_name.emplace(image.name, image);
    images.emplace_back(image.name, image.camera_id);
  }
  if (!options.rig_config_path.empty()) {
    const RigConfig rig = ReadRigConfig(options.rig_config_path);
    const std::vector<DatabaseCamera> cameras = database.ReadAllCameras();
    for (size_t i = 0; i < rig.cameras.size(); ++i) {
      const camera_t id = rig.cameras[i].camera_id;
      const bool found = std::any_of(
          cameras.begin(), cameras.end(),
          [id](const DatabaseCamera& c) { return c.camera_id == id; });
      if (!found) {
        throw ErrorAt(options.rig_config_path.string(), ": cameras[", i,
                      "].camera_id = ", id, ": ", database_name,
                      " has no such camera (its cameras: ", CameraIds(cameras),
                      ")");
      }
    }
  }
  const LoadedCameraPriors loaded =
      LoadCameraPriors(options, images, "the database " + database_name);
  const std::vector<NavRecord>& nav = loaded.nav;
  const RigConfig& rig = loaded.rig;
  const std::vector<CameraPrior>& priors = loaded.priors;

  PosePriorImportSummary summary;
  summary.schema = database.Schema();
  summary.num_database_images = image_of_name.size();
  summary.num_nav_rows = nav.size();
  summary.num_rig_cameras = rig.cameras.size();
  std::set<int> dives;
  for (const NavRecord& row : nav) dives.insert(row.dive);
  summary.num_dives = dives.size();
  std::vector<PosePrior> database_priors;
  for (const CameraPrior& prior : priors) {
    const PosePrior database_prior =
        DatabasePosePrior(prior, image_of_name.at(prior.image_name).image_id);
    summary.num_singular_covariances +=
        database_prior.HasPositionCovariance() ? 0 : 1;
    summary.num_exact += prior.sampling == NavSampling::kExact ? 1 : 0;
    summary.num_interpolated +=
        prior.sampling == NavSampling::kInterpolated ? 1 : 0;
    summary.num_extrapolated +=
        prior.sampling == NavSampling::kExtrapolated ? 1 : 0;
    database_priors.push_back(database_prior);
  }
  summary.num_priors = priors.size();
  summary.num_images_without_priors =
      summary.num_database_images - summary.num_priors;
  summary.other_images = loaded.other_images;
  summary.warnings = loaded.warnings;
  summary.frame = loaded.frame;
  summary.written = database.WritePosePriors(database_priors);
  return summary;
}

}  // namespace uw
