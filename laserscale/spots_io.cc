#include "laserscale/spots_io.h"

#include <algorithm>
#include <cmath>
#include <set>

#include <Eigen/Eigenvalues>
#include <nlohmann/json.hpp>

#include "common/util/error.h"
#include "common/util/file.h"
#include "common/util/json_fields.h"

namespace uw {
namespace {

constexpr char kFormat[] = "uwmetric-laser-spots";
constexpr int kVersion = 1;

// Empty if the spot's numbers are sound, else what is wrong.
std::string SpotProblem(const DetectedSpot& spot) {
  if (!(spot.detection_rate >= 0.0 && spot.detection_rate <= 1.0)) {
    return "detection_rate must be in [0, 1]";
  }
  if (!spot.pixel.allFinite()) return "pixel not finite";
  const Eigen::Matrix2d& cov = spot.covariance;
  if (!cov.allFinite()) return "covariance not finite";
  const double scale = std::max(cov.cwiseAbs().maxCoeff(), 1e-300);
  if (std::abs(cov(0, 1) - cov(1, 0)) > 1e-12 * scale) {
    return "covariance not symmetric";
  }
  const double min_eigenvalue =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(cov).eigenvalues()(0);
  if (min_eigenvalue < -1e-12 * scale) {
    return "covariance not positive semi-definite (eigenvalue " +
           std::to_string(min_eigenvalue) + ")";
  }
  if (spot.stable && !spot.detected) return "stable but not detected";
  return "";
}

std::string ImageWhere(const std::string& where, size_t index,
                       const std::string& name) {
  const std::string at = where + ": images[" + std::to_string(index) + "]";
  return name.empty() ? at : at + " \"" + name + "\"";
}

// An array of `n` finite numbers.
std::vector<double> Numbers(const nlohmann::json& json, size_t n,
                            const std::string& what) {
  if (!json.is_array() || json.size() != n ||
      !std::all_of(json.begin(), json.end(),
                   [](const nlohmann::json& x) { return x.is_number(); })) {
    throw ErrorAt(what, ": expected an array of ", n, " numbers, got ",
                  json.dump());
  }
  std::vector<double> values;
  for (const nlohmann::json& x : json) values.push_back(x.get<double>());
  return values;
}

DetectedSpot SpotFromJson(const nlohmann::json& json,
                          const std::string& where) {
  JsonFields fields(json, where);
  DetectedSpot spot;
  nlohmann::json pixel;
  nlohmann::json covariance;
  // Unknown keys first: a misspelt key is reported as such, not as the
  // required one it was meant to be.
  fields.Read("problem", &spot.problem);
  nlohmann::json declared;
  for (const char* key : {"laser", "detected", "stable", "detection_rate",
                          "pixel", "covariance"}) {
    fields.Read(key, &declared);
  }
  fields.RejectUnknown();
  fields.Require("laser", &spot.laser);
  fields.Require("detected", &spot.detected);
  fields.Require("stable", &spot.stable);
  fields.Require("detection_rate", &spot.detection_rate);
  fields.Require("pixel", &pixel);
  fields.Require("covariance", &covariance);
  const std::string what = where + " (laser " + spot.laser + ")";
  if (spot.laser.empty()) throw ErrorAt(where, ": empty laser name");
  const std::vector<double> xy = Numbers(pixel, 2, what + ".pixel");
  spot.pixel = {xy[0], xy[1]};
  if (!covariance.is_array() || covariance.size() != 2) {
    throw ErrorAt(what, ".covariance: expected 2 rows of 2 numbers, got ",
                  covariance.dump());
  }
  for (int r = 0; r < 2; ++r) {
    const std::vector<double> row =
        Numbers(covariance[r], 2, what + ".covariance");
    spot.covariance.row(r) << row[0], row[1];
  }
  const std::string problem = SpotProblem(spot);
  if (!problem.empty()) throw ErrorAt(what, ": ", problem);
  return spot;
}

}  // namespace

std::string SpotsJsonText(const std::vector<ImageSpots>& images) {
  nlohmann::json json_images = nlohmann::json::array();
  for (size_t i = 0; i < images.size(); ++i) {
    const ImageSpots& image = images[i];
    nlohmann::json spots = nlohmann::json::array();
    for (const DetectedSpot& spot : image.spots) {
      const std::string problem = SpotProblem(spot);
      if (!problem.empty()) {
        throw ErrorAt("spots.json: image \"", image.name, "\", laser ",
                      spot.laser, ": ", problem);
      }
      const Eigen::Matrix2d& cov = spot.covariance;
      spots.push_back(
          {{"laser", spot.laser},
           {"detected", spot.detected},
           {"stable", spot.stable},
           {"detection_rate", spot.detection_rate},
           {"pixel", {spot.pixel.x(), spot.pixel.y()}},
           {"covariance", {{cov(0, 0), cov(0, 1)}, {cov(1, 0), cov(1, 1)}}},
           {"problem", spot.problem}});
    }
    json_images.push_back(
        {{"name", image.name}, {"setup", image.setup}, {"spots", spots}});
  }
  const nlohmann::json json = {
      {"format", kFormat}, {"version", kVersion}, {"images", json_images}};
  return json.dump(2) + "\n";
}

std::vector<ImageSpots> ParseSpotsJson(const std::string& text,
                                       const std::string& where) {
  const nlohmann::json json = ParseJsonText(text, where);
  JsonFields file(json, where);
  nlohmann::json json_images;
  file.RequireFormat(kFormat, kVersion);
  file.Require("images", &json_images);
  file.RejectUnknown();
  if (!json_images.is_array()) {
    throw ErrorAt(where, ": \"images\" must be an array");
  }
  std::vector<ImageSpots> images;
  std::set<std::string> names;
  for (size_t i = 0; i < json_images.size(); ++i) {
    const nlohmann::json& entry = json_images[i];
    const bool named = entry.is_object() && entry.contains("name") &&
                       entry["name"].is_string();
    JsonFields fields(
        entry,
        ImageWhere(where, i, named ? entry["name"].get<std::string>() : ""));
    ImageSpots image;
    nlohmann::json json_spots;
    fields.Require("name", &image.name);
    fields.Require("setup", &image.setup);
    fields.Require("spots", &json_spots);
    fields.RejectUnknown();
    const std::string image_where = ImageWhere(where, i, image.name);
    if (image.name.empty()) throw ErrorAt(image_where, ": empty name");
    if (!names.insert(image.name).second) {
      throw ErrorAt(image_where, ": image listed twice");
    }
    if (!json_spots.is_array()) {
      throw ErrorAt(image_where, ".spots: expected an array");
    }
    std::set<std::string> lasers;
    for (size_t s = 0; s < json_spots.size(); ++s) {
      image.spots.push_back(SpotFromJson(
          json_spots[s], image_where + ".spots[" + std::to_string(s) + "]"));
      if (!lasers.insert(image.spots.back().laser).second) {
        throw ErrorAt(image_where, ": laser ", image.spots.back().laser,
                      " listed twice");
      }
    }
    images.push_back(std::move(image));
  }
  return images;
}

std::vector<ImageSpots> ReadSpotsJson(const std::filesystem::path& path) {
  return ParseSpotsJson(ReadFileToString(path), path.string());
}

}  // namespace uw
