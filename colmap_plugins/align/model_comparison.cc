#include "colmap_plugins/align/model_comparison.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>
#include <Eigen/Geometry>

#include "common/util/error.h"
#include "common/util/json_fields.h"

namespace uw {
namespace {

// The camera's viewing direction (its z axis) in the world: the last row
// of the cam_from_world rotation.
Eigen::Vector3d ViewDirection(const Eigen::Quaterniond& cam_from_world) {
  return cam_from_world.toRotationMatrix().row(2).transpose();
}

// The residuals of the model where it is.
SimilarityResult IdentityAlignment(
    const std::vector<Eigen::Vector3d>& model,
    const std::vector<Eigen::Vector3d>& reference) {
  SimilarityResult result;
  result.inliers.assign(model.size(), true);
  result.num_inliers = model.size();
  double squared_sum = 0.0;
  for (size_t k = 0; k < model.size(); ++k) {
    result.residuals.push_back(reference[k] - model[k]);
    squared_sum += result.residuals.back().squaredNorm();
  }
  result.rms_m = std::sqrt(squared_sum / model.size());
  return result;
}

SurfaceDeviation MeasureSurfaceDeviation(
    const Reconstruction& model, const Sim3d& reference_from_model,
    const MeshDistance& surface, const TrackAxis& axis,
    const ModelComparisonOptions& options) {
  std::map<image_t, Eigen::Vector3d> centres;
  for (const Image& image : model.Images()) {
    centres[image.image_id] = reference_from_model * image.ProjectionCenter();
  }
  SurfaceDeviation deviation;
  deviation.num_points = model.Points3D().size();
  std::vector<double> along_track;
  std::vector<double> distances;
  std::vector<double> abs_distances;
  double squared_sum = 0.0;
  double sum = 0.0;
  for (const Point3D& point3D : model.Points3D()) {
    if (point3D.HasError() &&
        point3D.error > options.max_reprojection_error_px) {
      continue;
    }
    Eigen::Vector3d viewpoint = Eigen::Vector3d::Zero();
    for (const TrackElement& element : point3D.track) {
      viewpoint += centres.at(element.image_id);
    }
    if (point3D.track.empty()) continue;
    viewpoint /= static_cast<double>(point3D.track.size());
    const Eigen::Vector3d point = reference_from_model * point3D.xyz;
    const double distance = surface.SignedDistance(point, viewpoint);
    along_track.push_back(axis.AlongTrack(point));
    distances.push_back(distance);
    abs_distances.push_back(std::abs(distance));
    squared_sum += distance * distance;
    sum += distance;
  }
  deviation.num_points_used = distances.size();
  if (distances.empty()) return deviation;
  const double n = static_cast<double>(distances.size());
  deviation.rms_m = std::sqrt(squared_sum / n);
  deviation.mean_m = sum / n;
  deviation.median_m = Quantile(distances, 0.5);
  deviation.median_abs_m = Quantile(abs_distances, 0.5);
  deviation.p95_abs_m = Quantile(abs_distances, 0.95);
  deviation.max_abs_m =
      *std::max_element(abs_distances.begin(), abs_distances.end());
  if (axis.length > 0.0) {
    deviation.bins = BinAlongTrack(along_track, distances, -0.5 * axis.length,
                                   0.5 * axis.length, options.num_bins);
    deviation.dome =
        FitDome(deviation.bins, axis.length, options.min_points_per_bin);
  }
  return deviation;
}

}  // namespace

void ModelComparisonOptions::Check() const {
  alignment.Check();
  if (num_segments < 1 || num_bins < 1) {
    throw ErrorAt("model comparison: segments (", num_segments, ") and bins (",
                  num_bins, ") must be >= 1");
  }
  if (!(max_reprojection_error_px > 0.0)) {
    throw ErrorAt(
        "model comparison: max_reprojection_error_px must be > 0, "
        "got ",
        max_reprojection_error_px);
  }
}

ModelComparison CompareModels(const Reconstruction& model,
                              const Reconstruction& reference,
                              const MeshDistance* reference_surface,
                              const ModelComparisonOptions& options) {
  options.Check();
  ModelComparison comparison;
  comparison.num_model_images = model.Images().size();
  comparison.num_reference_images = reference.Images().size();
  comparison.aligned = options.align;
  std::map<std::string, const Image*> model_images;
  for (const Image& image : model.Images()) model_images[image.name] = &image;
  std::map<std::string, const Image*> reference_images;
  for (const Image& image : reference.Images()) {
    reference_images[image.name] = &image;
  }
  // Name order: std::map iterates sorted.
  std::vector<std::pair<const Image*, const Image*>> common;
  for (const auto& [name, reference_image] : reference_images) {
    const auto it = model_images.find(name);
    if (it == model_images.end()) {
      comparison.missing_images.push_back(name);
    } else {
      common.emplace_back(it->second, reference_image);
    }
  }
  comparison.num_unmatched_model_images = model_images.size() - common.size();
  if (common.size() < 3) {
    throw ErrorAt(
        "model comparison: the model and the reference have ", common.size(),
        " image names in common; at least 3 are needed",
        model_images.empty() || reference_images.empty()
            ? std::string()
            : " (e.g. model '" + model_images.begin()->first +
                  "', reference '" + reference_images.begin()->first + "')");
  }

  std::vector<Eigen::Vector3d> model_centres;
  std::vector<Eigen::Vector3d> reference_centres;
  for (const auto& [model_image, reference_image] : common) {
    model_centres.push_back(model_image->ProjectionCenter());
    reference_centres.push_back(reference_image->ProjectionCenter());
  }
  if (options.align) {
    comparison.alignment = EstimateSimilarity(model_centres, reference_centres,
                                              nullptr, options.alignment);
  } else {
    comparison.alignment = IdentityAlignment(model_centres, reference_centres);
  }
  const Sim3d& reference_from_model = comparison.alignment.b_from_a;
  comparison.axis = TrackAxisFromCentres(reference_centres);
  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3d& centre : reference_centres) box.extend(centre);
  comparison.reference_extent_m = box.diagonal().norm();

  std::vector<Eigen::Vector3d> aligned_centres;
  std::vector<Eigen::Vector3d> aligned_views;
  std::vector<Eigen::Vector3d> reference_views;
  double squared_sum = 0.0;
  double rotation_squared_sum = 0.0;
  const Eigen::Quaterniond model_from_reference_rotation =
      reference_from_model.rotation.inverse();
  for (size_t k = 0; k < common.size(); ++k) {
    const auto& [model_image, reference_image] = common[k];
    CameraDeviation camera;
    camera.name = reference_image->name;
    camera.position_error_m = -comparison.alignment.residuals[k];
    // cam_from_reference = cam_from_model * model_from_reference.
    const Eigen::Quaterniond aligned_rotation =
        model_image->cam_from_world.rotation.normalized() *
        model_from_reference_rotation;
    camera.rotation_error_deg =
        aligned_rotation.angularDistance(
            reference_image->cam_from_world.rotation.normalized()) *
        180.0 / M_PI;
    camera.along_track_m = comparison.axis.AlongTrack(reference_centres[k]);
    camera.inlier = comparison.alignment.inliers[k];
    squared_sum += camera.position_error_m.squaredNorm();
    rotation_squared_sum +=
        camera.rotation_error_deg * camera.rotation_error_deg;
    comparison.camera_max_error_m =
        std::max(comparison.camera_max_error_m, camera.position_error_m.norm());
    comparison.rotation_max_deg =
        std::max(comparison.rotation_max_deg, camera.rotation_error_deg);
    aligned_centres.push_back(reference_from_model * model_centres[k]);
    aligned_views.push_back(ViewDirection(aligned_rotation));
    reference_views.push_back(
        ViewDirection(reference_image->cam_from_world.rotation.normalized()));
    comparison.cameras.push_back(camera);
  }
  comparison.camera_rmse_m = std::sqrt(squared_sum / common.size());
  comparison.rotation_rmse_deg =
      std::sqrt(rotation_squared_sum / common.size());
  comparison.segments =
      PerSegmentScale(aligned_centres, reference_centres, aligned_views,
                      reference_views, comparison.axis, options.num_segments);
  comparison.distance_ratios =
      CameraDistanceRatios(model_centres, reference_centres);
  if (reference_surface != nullptr) {
    comparison.surface =
        MeasureSurfaceDeviation(model, reference_from_model, *reference_surface,
                                comparison.axis, options);
  }
  return comparison;
}

namespace {

nlohmann::json ToJson(const DeviationBin& bin) {
  return {{"begin_m", bin.begin},
          {"end_m", bin.end},
          {"count", bin.count},
          {"median_m", bin.median_m}};
}

}  // namespace

nlohmann::json ToJson(const ModelComparison& comparison) {
  nlohmann::json cameras = nlohmann::json::array();
  for (const CameraDeviation& camera : comparison.cameras) {
    cameras.push_back(
        {{"name", camera.name},
         {"position_error_m", ToJson(camera.position_error_m)},
         {"position_error_norm_m", camera.position_error_m.norm()},
         {"rotation_error_deg", camera.rotation_error_deg},
         {"along_track_m", camera.along_track_m},
         {"inlier", camera.inlier}});
  }
  nlohmann::json segments = nlohmann::json::array();
  for (const SegmentScale& segment : comparison.segments) {
    segments.push_back({{"begin_m", segment.begin},
                        {"end_m", segment.end},
                        {"num_images", segment.num_images},
                        {"num_steps", segment.num_steps},
                        {"scale_3d", segment.scale_3d},
                        {"scale_along_track", segment.scale_along_track},
                        {"view_tilt_deg", segment.view_tilt_deg}});
  }
  const SimilarityResult& alignment = comparison.alignment;
  nlohmann::json json = {
      {"format", "uwmetric-model-comparison"},
      {"version", 1},
      {"num_model_images", comparison.num_model_images},
      {"num_reference_images", comparison.num_reference_images},
      {"num_common_images", comparison.cameras.size()},
      {"missing_images", comparison.missing_images},
      {"num_unmatched_model_images", comparison.num_unmatched_model_images},
      {"alignment",
       {{"aligned", comparison.aligned},
        {"reference_from_model", ToJson(alignment.b_from_a)},
        {"num_inliers", alignment.num_inliers},
        {"rms_m", alignment.rms_m}}},
      {"reference_extent_m", comparison.reference_extent_m},
      {"camera_rmse_m", comparison.camera_rmse_m},
      {"camera_rmse_percent_of_extent",
       100.0 * comparison.camera_rmse_m / comparison.reference_extent_m},
      {"camera_max_error_m", comparison.camera_max_error_m},
      {"rotation_rmse_deg", comparison.rotation_rmse_deg},
      {"rotation_max_deg", comparison.rotation_max_deg},
      {"track",
       {{"origin", ToJson(comparison.axis.origin)},
        {"direction", ToJson(comparison.axis.direction)},
        {"length_m", comparison.axis.length}}},
      {"segments", segments},
      {"distance_ratios",
       {{"num_pairs", comparison.distance_ratios.num_pairs},
        {"median_ratio", comparison.distance_ratios.median_ratio},
        {"max_abs_deviation", comparison.distance_ratios.max_abs_deviation},
        {"p95_abs_deviation", comparison.distance_ratios.p95_abs_deviation}}},
      {"cameras", cameras}};
  if (comparison.surface) {
    const SurfaceDeviation& surface = *comparison.surface;
    nlohmann::json bins = nlohmann::json::array();
    for (const DeviationBin& bin : surface.bins) bins.push_back(ToJson(bin));
    json["surface"] = {{"num_points", surface.num_points},
                       {"num_points_used", surface.num_points_used},
                       {"rms_m", surface.rms_m},
                       {"mean_m", surface.mean_m},
                       {"median_m", surface.median_m},
                       {"median_abs_m", surface.median_abs_m},
                       {"p95_abs_m", surface.p95_abs_m},
                       {"max_abs_m", surface.max_abs_m},
                       {"bins", bins},
                       {"dome",
                        {{"valid", surface.dome.valid},
                         {"num_bins_used", surface.dome.num_bins_used},
                         {"coefficients", surface.dome.coefficients},
                         {"sagitta_m", surface.dome.sagitta_m},
                         {"sagitta_percent", surface.dome.sagitta_percent}}}};
  } else {
    json["surface"] = nullptr;
  }
  return json;
}

std::string FormatModelComparison(const ModelComparison& comparison,
                                  const std::string& surface_path,
                                  const ModelComparisonOptions& options) {
  std::string text = fmt::format(
      "Images: model {}, reference {}, common {} (reference images "
      "missing from the model: {}{}{})\n",
      comparison.num_model_images, comparison.num_reference_images,
      comparison.cameras.size(), comparison.missing_images.size(),
      comparison.missing_images.empty() ? "" : ", e.g. ",
      comparison.missing_images.empty() ? ""
                                        : comparison.missing_images.front());
  if (comparison.aligned) {
    text += fmt::format(
        "Alignment reference_from_model ({}{}): scale {:.8g}, {} of {} "
        "inliers\n",
        options.alignment.estimate_scale ? "similarity, " : "rigid, ",
        options.alignment.robust ? "robust" : "least squares",
        comparison.alignment.b_from_a.scale, comparison.alignment.num_inliers,
        comparison.cameras.size());
  } else {
    text += "Alignment: none (the model is compared where it is)\n";
  }
  text += fmt::format(
      "Camera centres: RMSE {:.6g} m = {:.4f} % of the {:.4g} m extent, max "
      "{:.6g} m\n",
      comparison.camera_rmse_m,
      100.0 * comparison.camera_rmse_m / comparison.reference_extent_m,
      comparison.reference_extent_m, comparison.camera_max_error_m);
  text +=
      fmt::format("Camera rotations: RMS {:.6g} deg, max {:.6g} deg\n",
                  comparison.rotation_rmse_deg, comparison.rotation_max_deg);
  text +=
      fmt::format("Track: {:.6g} m along ({:.4f}, {:.4f}, {:.4f})\n",
                  comparison.axis.length, comparison.axis.direction.x(),
                  comparison.axis.direction.y(), comparison.axis.direction.z());
  text += fmt::format("{:<8} {:>10} {:>10} {:>7} {:>10} {:>12} {:>10}\n",
                      "segment", "from_m", "to_m", "images", "scale_3d",
                      "scale_along", "tilt_deg");
  for (size_t s = 0; s < comparison.segments.size(); ++s) {
    const SegmentScale& segment = comparison.segments[s];
    text +=
        fmt::format("{:<8} {:10.3f} {:10.3f} {:7} {:10.5f} {:12.5f} {:10.3f}\n",
                    static_cast<char>('A' + s), segment.begin, segment.end,
                    segment.num_images, segment.scale_3d,
                    segment.scale_along_track, segment.view_tilt_deg);
  }
  const DistanceRatios& ratios = comparison.distance_ratios;
  text += fmt::format(
      "Camera distance ratios model/reference ({} pairs): median {:.6g}, max "
      "|r-1| {:.4g}, 95 % |r-1| {:.4g}\n",
      ratios.num_pairs, ratios.median_ratio, ratios.max_abs_deviation,
      ratios.p95_abs_deviation);
  if (!comparison.surface) return text;
  const SurfaceDeviation& surface = *comparison.surface;
  text += fmt::format(
      "Surface {}: {} of {} points (error <= {:g} px), signed distance "
      "(+ towards the cameras): RMS {:.6g} m, mean {:.6g} m, median {:.6g} m, "
      "median |d| {:.6g} m, 95 % |d| {:.6g} m, max |d| {:.6g} m\n",
      surface_path, surface.num_points_used, surface.num_points,
      options.max_reprojection_error_px, surface.rms_m, surface.mean_m,
      surface.median_m, surface.median_abs_m, surface.p95_abs_m,
      surface.max_abs_m);
  text += fmt::format("{:<8} {:>10} {:>10} {:>8} {:>12}\n", "bin", "from_m",
                      "to_m", "points", "median_m");
  for (size_t b = 0; b < surface.bins.size(); ++b) {
    const DeviationBin& bin = surface.bins[b];
    text += fmt::format("{:<8} {:10.3f} {:10.3f} {:8} {:12.6f}\n", b + 1,
                        bin.begin, bin.end, bin.count, bin.median_m);
  }
  if (surface.dome.valid) {
    text += fmt::format(
        "Dome fit d(x) = {:.4g} + {:.4g} x + {:.4g} x^2: sagitta {:.6g} m = "
        "{:.4f} % of the track (negative: the middle stands out towards the "
        "cameras)\n",
        surface.dome.coefficients[0], surface.dome.coefficients[1],
        surface.dome.coefficients[2], surface.dome.sagitta_m,
        surface.dome.sagitta_percent);
  } else {
    text += fmt::format("Dome fit: fewer than 3 bins with {} points\n",
                        options.min_points_per_bin);
  }
  return text;
}

}  // namespace uw
