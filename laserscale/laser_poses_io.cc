#include "laserscale/laser_poses_io.h"

#include <cmath>

#include <nlohmann/json.hpp>

#include "common/util/error.h"
#include "common/util/file.h"
#include "common/util/json_fields.h"

namespace uw {
namespace {

constexpr char kFormat[] = "uwmetric-laser-poses";
// Version 2 adds each inlier's point3D_id; version 1 files still read.
constexpr int kVersion = 2;

template <typename T>
void CheckFinite(const T& values, const std::string& where) {
  for (const double value : values) {
    if (!std::isfinite(value)) throw ErrorAt(where, ": not finite");
  }
}

}  // namespace

std::string LaserPosesJsonText(const std::vector<LocalizedImage>& images) {
  nlohmann::json json_images = nlohmann::json::array();
  for (const LocalizedImage& image : images) {
    nlohmann::json entry = {
        {"name", image.name},
        {"success", image.success},
        {"problem", image.problem},
        {"camera",
         {{"camera_id", image.camera.camera_id},
          {"model", image.camera.ModelName()},
          {"width", image.camera.width},
          {"height", image.camera.height},
          {"params", image.camera.params}}},
        {"num_matches", image.num_matches},
        {"num_matched_model_images", image.num_matched_model_images}};
    if (image.success) {
      const Eigen::Quaterniond& q = image.cam_from_world.rotation;
      entry["cam_from_world"] = {
          {"rotation_wxyz", {q.w(), q.x(), q.y(), q.z()}},
          {"translation", ToJson(image.cam_from_world.translation)}};
      entry["rms_error_px"] = image.rms_error_px;
      nlohmann::json inliers = nlohmann::json::array();
      for (const Correspondence2D3D& match : image.inliers) {
        nlohmann::json row = {
            match.pixel.x(), match.pixel.y(), match.point_in_world.x(),
            match.point_in_world.y(), match.point_in_world.z()};
        // -1: the match has no model point id (made by another program).
        if (match.point3D_id == kInvalidPoint3DId) {
          row.push_back(-1);
        } else {
          row.push_back(match.point3D_id);
        }
        inliers.push_back(row);
      }
      entry["inliers"] = inliers;
    }
    json_images.push_back(entry);
  }
  const nlohmann::json json = {
      {"format", kFormat},
      {"version", kVersion},
      {"inliers",
       "[x, y, X, Y, Z, point3D_id]: COLMAP pixel, model point (-1: no id)"},
      {"images", json_images}};
  return json.dump(1) + "\n";
}

std::vector<LocalizedImage> ParseLaserPosesJson(const std::string& text,
                                                const std::string& where) {
  const nlohmann::json json = ParseJsonText(text, where);
  JsonFields file(json, where);
  const int version = file.RequireFormat(kFormat, 1, kVersion);
  const size_t row_size = version == 1 ? 5 : 6;
  std::string inliers_doc;
  nlohmann::json json_images;
  file.Read("inliers", &inliers_doc);
  file.Require("images", &json_images);
  file.RejectUnknown();
  if (!json_images.is_array()) {
    throw ErrorAt(where, ": \"images\" must be an array");
  }
  std::vector<LocalizedImage> images;
  for (size_t i = 0; i < json_images.size(); ++i) {
    LocalizedImage image;
    const std::string image_where =
        where + ": images[" + std::to_string(i) + "]";
    JsonFields fields(json_images[i], image_where);
    fields.Require("name", &image.name);
    const std::string named = where + ": image '" + image.name + "'";
    nlohmann::json camera;
    nlohmann::json pose;
    nlohmann::json inliers;
    fields.Require("success", &image.success);
    fields.Read("problem", &image.problem);
    fields.Require("camera", &camera);
    fields.Read("num_matches", &image.num_matches);
    fields.Read("num_matched_model_images", &image.num_matched_model_images);
    fields.Read("cam_from_world", &pose);
    fields.Read("rms_error_px", &image.rms_error_px);
    fields.Read("inliers", &inliers);
    fields.RejectUnknown();

    JsonFields camera_fields(camera, named + ": camera");
    std::string model;
    camera_fields.Require("camera_id", &image.camera.camera_id);
    camera_fields.Require("model", &model);
    camera_fields.Require("width", &image.camera.width);
    camera_fields.Require("height", &image.camera.height);
    camera_fields.Require("params", &image.camera.params);
    camera_fields.RejectUnknown();
    image.camera.model_id = CameraModelNameToId(model);
    if (image.camera.model_id == CameraModelId::kInvalid) {
      throw ErrorAt(named, ": unknown camera model '", model, "'");
    }
    try {
      CheckCameraModelParams(image.camera.model_id, image.camera.params.size());
    } catch (const Error& error) {
      throw ErrorAt(named, ": ", error.what());
    }
    CheckFinite(image.camera.params, named + ": camera params");

    if (image.success) {
      JsonFields pose_fields(pose, named + ": cam_from_world");
      std::vector<double> rotation;
      Eigen::Vector3d translation;
      pose_fields.Require("rotation_wxyz", &rotation);
      pose_fields.Require("translation", &translation);
      pose_fields.RejectUnknown();
      if (rotation.size() != 4) {
        throw ErrorAt(named, ": rotation_wxyz must have 4 numbers");
      }
      CheckFinite(rotation, named + ": rotation_wxyz");
      CheckFinite(translation, named + ": translation");
      image.cam_from_world.rotation = Eigen::Quaterniond(
          rotation[0], rotation[1], rotation[2], rotation[3]);
      if (std::abs(image.cam_from_world.rotation.norm() - 1.0) > 1e-6) {
        throw ErrorAt(named, ": rotation_wxyz is not a unit quaternion");
      }
      image.cam_from_world.translation = translation;
      if (!inliers.is_array()) {
        throw ErrorAt(named, ": a localized image needs its \"inliers\"");
      }
      for (size_t k = 0; k < inliers.size(); ++k) {
        const std::string row_where =
            named + ": inliers[" + std::to_string(k) + "]";
        if (!inliers[k].is_array() || inliers[k].size() != row_size) {
          throw ErrorAt(
              row_where, " must be ",
              version == 1 ? "[x, y, X, Y, Z]" : "[x, y, X, Y, Z, point3D_id]");
        }
        std::vector<double> row;
        for (size_t c = 0; c < 5; ++c) {
          if (!inliers[k][c].is_number()) {
            throw ErrorAt(row_where, ": entry ", c, " is not a number");
          }
          row.push_back(inliers[k][c].get<double>());
        }
        CheckFinite(row, row_where);
        Correspondence2D3D match{Eigen::Vector2d(row[0], row[1]),
                                 Eigen::Vector3d(row[2], row[3], row[4])};
        if (version >= 2) {
          const nlohmann::json& id = inliers[k][5];
          if (id.is_number_unsigned()) {
            match.point3D_id = id.get<point3D_t>();
          } else if (!(id.is_number_integer() && id.get<int64_t>() == -1)) {
            throw ErrorAt(row_where, ": point3D_id must be an id or -1, got ",
                          id.dump());
          }
        }
        image.inliers.push_back(match);
      }
      if (!(image.rms_error_px >= 0.0) || !std::isfinite(image.rms_error_px)) {
        throw ErrorAt(named, ": rms_error_px must be finite and >= 0");
      }
    }
    images.push_back(std::move(image));
  }
  return images;
}

std::vector<LocalizedImage> ReadLaserPosesJson(
    const std::filesystem::path& path) {
  return ParseLaserPosesJson(ReadFileToString(path), path.string());
}

}  // namespace uw
