#include "report/report_inputs.h"

#include <algorithm>

#include <nlohmann/json.hpp>

#include "common/util/error.h"
#include "common/util/file.h"
#include "common/util/json_fields.h"

namespace uw {
namespace fs = std::filesystem;
namespace {

using Json = nlohmann::json;

Json ReadJsonFile(const fs::path& path, const std::string& format) {
  const Json json = ParseJsonText(ReadFileToString(path), path.string());
  if (!json.is_object() || json.value("format", "") != format) {
    throw ErrorAt(path.string(), ": expected a JSON object of format \"",
                  format, "\"");
  }
  return json;
}

// A required value of `json` at `key`, converted; the error names the file
// and the key.
template <typename T>
T Get(const Json& json, const std::string& key, const fs::path& path) {
  const auto it = json.find(key);
  if (it == json.end() || it->is_null()) {
    throw ErrorAt(path.string(), ": missing key \"", key, "\"");
  }
  try {
    return it->get<T>();
  } catch (const Json::exception& error) {
    throw ErrorAt(path.string(), ": key \"", key, "\": ", error.what());
  }
}

template <typename T>
std::optional<T> GetOptional(const Json& json, const std::string& key,
                             const fs::path& path) {
  if (!json.contains(key) || json.at(key).is_null()) return std::nullopt;
  return Get<T>(json, key, path);
}

Eigen::Vector3d GetVector3(const Json& json, const std::string& key,
                           const fs::path& path) {
  const std::vector<double> values = Get<std::vector<double>>(json, key, path);
  if (values.size() != 3) {
    throw ErrorAt(path.string(), ": key \"", key,
                  "\": expected 3 numbers, got ", values.size());
  }
  return Eigen::Vector3d(values[0], values[1], values[2]);
}

void RequireExists(const fs::path& path, const char* flag, bool folder) {
  if (path.empty()) return;
  if (folder ? !fs::is_directory(path) : !fs::is_regular_file(path)) {
    throw ErrorAt(flag, " ", path.string(), ": no such ",
                  folder ? "folder" : "file");
  }
}

}  // namespace

void SurveyReportInputs::Check() const {
  if (model_path.empty()) throw ErrorAt("--input_path: a model is required");
  RequireExists(model_path, "--input_path", true);
  RequireExists(ba_report_path, "--ba_report", false);
  RequireExists(nav_path, "--nav", false);
  RequireExists(laser_report_dir, "--laser_report", true);
  RequireExists(compare_table_path, "--compare_table", false);
  RequireExists(dense_comparison_path, "--dense_comparison", false);
  RequireExists(mesh_path, "--mesh", false);
  RequireExists(timings_path, "--timings", false);
  RequireExists(truth_dir, "--truth_dir", true);
  RequireExists(covariance_dir, "--covariance", true);
}

BaReportSummary ReadBaReport(const fs::path& path) {
  const Json json = ReadJsonFile(path, "uwmetric-ba-report");
  BaReportSummary summary;
  summary.weight_px_per_m = Get<double>(json, "weight_px_per_m", path);
  summary.weighting = json.value("weighting", "");
  if (json.contains("run") && json["run"].is_object()) {
    summary.strategy = json["run"].value("strategy", "");
  }
  summary.nav_sigma_m = GetOptional<double>(json, "nav_sigma_m", path);
  summary.prior_residual_rms_m =
      GetOptional<double>(json, "prior_residual_rms_m", path);
  for (const Json& item : json.value("prior_residuals", Json::array())) {
    BaReportSummary::Residual residual;
    residual.name = Get<std::string>(item, "name", path);
    residual.dive = item.value("dive", 1);
    residual.error_m = GetVector3(item, "error_m", path);
    residual.error_norm_m = Get<double>(item, "error_norm_m", path);
    residual.mahalanobis = GetOptional<double>(item, "mahalanobis", path);
    summary.residuals.push_back(std::move(residual));
  }
  for (const Json& item : json.value("dive_offsets", Json::array())) {
    BaReportSummary::DiveOffset offset;
    offset.dive = Get<int>(item, "dive", path);
    offset.num_images = item.value("num_images", 0);
    offset.offset_m = GetVector3(item, "offset_m", path);
    if (item.contains("sigma_m")) {
      offset.sigma_m = GetVector3(item, "sigma_m", path);
    }
    summary.dive_offsets.push_back(offset);
  }
  summary.warnings = json.value("warnings", std::vector<std::string>{});
  return summary;
}

LaserReportSummary ReadLaserReport(const fs::path& dir) {
  const fs::path scale_path = dir / "scale.json";
  if (!fs::is_regular_file(scale_path)) {
    throw ErrorAt(scale_path.string(),
                  ": missing (expected an output folder of laserscale "
                  "estimate)");
  }
  const Json json = ReadJsonFile(scale_path, "uwmetric-laser-scale");
  LaserReportSummary summary;
  summary.dir = dir;
  summary.method = json.value("method", "");
  summary.scale = GetOptional<double>(json, "scale", scale_path);
  if (summary.scale) {
    summary.sigma = Get<double>(json, "sigma", scale_path);
    const std::vector<double> ci =
        Get<std::vector<double>>(json, "ci95", scale_path);
    if (ci.size() != 2) {
      throw ErrorAt(scale_path.string(), ": ci95 must hold 2 numbers");
    }
    summary.ci95_low = ci[0];
    summary.ci95_high = ci[1];
    summary.birge_ratio = json.value("birge_ratio", 0.0);
  }
  summary.num_images = json.value("num_images", 0);
  summary.num_accepted = json.value("num_accepted", 0);
  summary.num_iterations = json.value("num_iterations", 0);
  for (const char* name : {"items.csv", "segments.csv"}) {
    if (!fs::is_regular_file(dir / name)) continue;
    (std::string(name) == "items.csv" ? summary.items : summary.segments) =
        CsvTable::Read(dir / name);
  }
  for (const char* name : {"scales.png", "histogram.png", "convergence.png"}) {
    if (fs::is_regular_file(dir / name)) summary.plots.push_back(dir / name);
  }
  if (fs::is_directory(dir / "overlays")) {
    for (const auto& entry : fs::directory_iterator(dir / "overlays")) {
      if (entry.is_regular_file() && IsImageFile(entry.path())) {
        summary.overlays.push_back(entry.path());
      }
    }
    std::sort(summary.overlays.begin(), summary.overlays.end());
  }
  if (json.contains("model_draws")) {
    const Json& draws = json["model_draws"];
    summary.model_draws = Get<int>(draws, "count", scale_path);
    summary.model_gauge = draws.value("gauge", "");
  }
  const Json shares = json.value("variance_by_source", Json::object());
  for (const auto& [source, share] : shares.items()) {
    summary.variance_shares.emplace_back(
        source, Get<double>(share, "share", scale_path));
  }
  if (json.contains("navigation")) {
    summary.navigation_z = Get<double>(json["navigation"], "z", scale_path);
    summary.navigation_consistent =
        Get<bool>(json["navigation"], "consistent", scale_path);
  }
  return summary;
}

CovarianceSummary ReadCovarianceSummary(const fs::path& dir) {
  const fs::path path = dir / "covariance.json";
  if (!fs::is_regular_file(path)) {
    throw ErrorAt(path.string(),
                  ": missing (expected an output folder of uwcolmap "
                  "covariance_estimator)");
  }
  const Json json = ReadJsonFile(path, "uwmetric-covariance");
  const auto quantiles = [&](const Json& parent, const std::string& key) {
    const Json& value = Get<Json>(parent, key, path);
    return CovarianceSummary::Quantiles{Get<double>(value, "median", path),
                                        Get<double>(value, "p95", path),
                                        Get<double>(value, "max", path)};
  };
  CovarianceSummary summary;
  summary.dir = dir;
  summary.gauge = Get<std::string>(json, "gauge", path);
  summary.gauge_description = json.value("gauge_description", "");
  summary.pixel_sigma_px = Get<double>(json, "pixel_sigma_px", path);
  summary.pixel_sigma_source = json.value("pixel_sigma_source", "");
  summary.nav_sigma_scale = json.value("nav_sigma_scale", 1.0);
  summary.nav_sigma_source = json.value("nav_sigma_source", "");
  summary.num_images = Get<int>(json, "num_images", path);
  summary.num_points = Get<int>(json, "num_points", path);
  const Json& images = Get<Json>(json, "images", path);
  summary.centre_sigma_m = quantiles(images, "sigma_position_m");
  summary.rotation_sigma_deg = quantiles(images, "sigma_rotation_deg");
  if (json.contains("points") &&
      json["points"].contains("sigma_largest_axis_m")) {
    summary.point_sigma_m = quantiles(json["points"], "sigma_largest_axis_m");
    summary.num_weak_points = json["points"].value("num_weak", 0);
  }
  summary.warnings = json.value("warnings", std::vector<std::string>{});
  if (json.contains("samples")) {
    const Json& samples = json["samples"];
    summary.num_samples = Get<int>(samples, "count", path);
    summary.log_scale_sigma = Get<double>(samples, "log_scale_sigma", path);
    summary.log_scale_meaning = samples.value("log_scale_meaning", "");
  }
  summary.cameras = CsvTable::Read(
      dir / "cameras.csv",
      {"image_id", "name", "held", "num_points", "sigma_x_m", "sigma_y_m",
       "sigma_z_m", "sigma_position_m", "sigma_rotation_deg"},
      {"name", "held", "num_points", "sigma_position_m", "sigma_rotation_deg"});
  if (fs::is_regular_file(dir / "uncertainty_map.png")) {
    summary.map = dir / "uncertainty_map.png";
  }
  return summary;
}

DenseComparisonSummary ReadDenseComparison(const fs::path& path) {
  const Json json = ReadJsonFile(path, "uwmetric-model-comparison");
  const auto dense = json.find("dense_surface");
  if (dense == json.end() || !dense->is_object()) {
    throw ErrorAt(path.string(),
                  ": no dense_surface block (run model_comparer with "
                  "--dense_mesh_path)");
  }
  DenseComparisonSummary summary;
  if (json.contains("alignment") && json["alignment"].is_object() &&
      json["alignment"].contains("reference_from_model")) {
    summary.reference_from_model_scale =
        Get<double>(json["alignment"]["reference_from_model"], "scale", path);
  }
  const Json& d = *dense;
  summary.camera_scene_distance = Get<double>(d, "camera_scene_distance", path);
  summary.median_distance = Get<double>(d, "median_distance", path);
  summary.p90_distance = Get<double>(d, "p90_distance", path);
  summary.rms_distance = Get<double>(d, "rms_distance", path);
  summary.mean_signed_distance = Get<double>(d, "mean_signed_distance", path);
  summary.observed_area = Get<double>(d, "observed_area", path);
  summary.covered_area = Get<double>(d, "covered_area", path);
  summary.coverage = Get<double>(d, "coverage", path);
  summary.coverage_tolerance = Get<double>(d, "coverage_tolerance", path);
  summary.num_samples = Get<size_t>(d, "num_samples", path);
  return summary;
}

std::vector<StageTime> ReadTimings(const fs::path& path) {
  const CsvTable file = CsvTable::Read(path);
  std::vector<StageTime> stages;
  for (size_t row = 0; row < file.NumRows(); ++row) {
    const std::optional<double> seconds = file.Number(row, "seconds");
    if (!seconds) throw ErrorAt(file.Where(row), ": no seconds");
    stages.push_back({file.Text(row, "stage"), *seconds});
  }
  return stages;
}

}  // namespace uw
