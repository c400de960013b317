#include "colmap_plugins/align/alignment_plausibility.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "common/util/error.h"
#include "common/util/median.h"

namespace uw {

std::vector<double> ObservationDepths(const Reconstruction& model) {
  std::vector<double> depths;
  for (const Point3D& point : model.Points3D()) {
    for (const TrackElement& element : point.track) {
      const Image* image = model.FindImage(element.image_id);
      if (image == nullptr) continue;
      depths.push_back((image->cam_from_world * point.xyz).z());
    }
  }
  return depths;
}

void AlignmentPlausibilityOptions::Check() const {
  if (!(min_range_m > 0.0 && max_range_m > min_range_m &&
        std::isfinite(max_range_m))) {
    throw ErrorAt("plausible imaging range ", min_range_m, " to ", max_range_m,
                  " m: expected 0 < min < max < inf");
  }
  if (!(min_explained >= 0.0 && min_explained < 1.0)) {
    throw ErrorAt("min_explained ", min_explained, ": expected [0, 1)");
  }
  if (!(min_inlier_fraction >= 0.0 && min_inlier_fraction <= 1.0)) {
    throw ErrorAt("min_inlier_fraction ", min_inlier_fraction,
                  ": expected [0, 1]");
  }
  if (!(min_sigma_ratio > 0.0 && max_sigma_ratio > min_sigma_ratio &&
        refuse_sigma_ratio >= max_sigma_ratio &&
        std::isfinite(refuse_sigma_ratio))) {
    throw ErrorAt("sigma ratios ", min_sigma_ratio, ", ", max_sigma_ratio, ", ",
                  refuse_sigma_ratio,
                  ": expected 0 < min < max <= refuse < inf");
  }
}

AlignmentPlausibility CheckAlignmentPlausibility(
    const Reconstruction& model, const SimilarityResult& similarity,
    const std::vector<Eigen::Vector3d>& references, const std::string& what,
    const AlignmentPlausibilityOptions& options) {
  options.Check();
  if (references.size() != similarity.residuals.size() ||
      similarity.inliers.size() != similarity.residuals.size()) {
    throw ErrorAt("alignment plausibility: ", references.size(),
                  " references against ", similarity.residuals.size(),
                  " residuals");
  }
  AlignmentPlausibility result;
  const double scale = similarity.b_from_a.scale;
  const std::vector<double> depths = ObservationDepths(model);
  result.num_depths = depths.size();
  if (!depths.empty()) {
    result.median_range_m = scale * Median(depths);
    const double range = *result.median_range_m;
    const std::string seen = fmt::format(
        "{}: at the similarity's scale {:.3g} the cameras see their scene "
        "from {:.3g} m (median of {} point depths)",
        what, scale, range, depths.size());
    if (range < options.min_range_m) {
      result.errors.push_back(fmt::format(
          "{}, and no camera maps from closer than {:g} m. Are the positions "
          "latitude/longitude in degrees, or another unit, read as metres?",
          seen, options.min_range_m));
    } else if (range > options.max_range_m) {
      result.errors.push_back(fmt::format(
          "{}, and no camera sees farther than {:g} m underwater. Are the "
          "positions in millimetres or centimetres read as metres?",
          seen, options.max_range_m));
    }
  }

  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  size_t num_inliers = 0;
  for (size_t k = 0; k < references.size(); ++k) {
    if (!similarity.inliers[k]) continue;
    mean += references[k];
    ++num_inliers;
  }
  const std::string another_time =
      "Are they paired with the navigation of another time (a camera clock "
      "offset: --time_offset), or is the log of another survey?";
  if (static_cast<double>(num_inliers) <
      options.min_inlier_fraction * static_cast<double>(references.size())) {
    result.errors.push_back(fmt::format(
        "{}: only {} of the {} positions agree with the similarity, which "
        "then fits the few that happen to. {}",
        what, num_inliers, references.size(), another_time));
  }
  if (num_inliers == 0) return result;
  mean /= static_cast<double>(num_inliers);
  double spread = 0.0;
  double residual = 0.0;
  double mahalanobis = 0.0;
  for (size_t k = 0; k < references.size(); ++k) {
    if (!similarity.inliers[k]) continue;
    spread += (references[k] - mean).squaredNorm();
    residual += similarity.residuals[k].squaredNorm();
    if (!similarity.mahalanobis.empty()) {
      mahalanobis += similarity.mahalanobis[k] * similarity.mahalanobis[k];
    }
  }
  result.explained = spread > 0.0 ? 1.0 - residual / spread : 0.0;
  if (!similarity.mahalanobis.empty()) {
    result.sigma_ratio =
        std::sqrt(mahalanobis / (3.0 * static_cast<double>(num_inliers)));
  }
  const double n = static_cast<double>(num_inliers);
  const bool sigmas_explain = result.sigma_ratio.has_value() &&
                              *result.sigma_ratio <= options.max_sigma_ratio;
  if (result.explained < options.min_explained && !sigmas_explain) {
    const bool noisier_than_stated =
        result.sigma_ratio && *result.sigma_ratio <= options.refuse_sigma_ratio;
    const std::string text = fmt::format(
        "{}: the similarity explains {:.0f} % of the spread of the {} "
        "positions (residual RMS {:.3g} m against a spread of {:.3g} m "
        "RMS{}): {}. {}{}",
        what, 100.0 * std::max(result.explained, 0.0), num_inliers,
        std::sqrt(residual / n), std::sqrt(spread / n),
        result.sigma_ratio ? fmt::format(", {:.3g} times the stated sigmas",
                                         *result.sigma_ratio)
                           : std::string(),
        noisier_than_stated
            ? "the navigation is much noisier than it states, or does not "
              "follow these images"
            : "the navigation does not follow these images",
        another_time,
        result.sigma_ratio ? ""
                           : " Or is the positions' noise, which they do not "
                             "state, as large as the survey?");
    (noisier_than_stated ? result.warnings : result.errors).push_back(text);
  }
  if (result.sigma_ratio && *result.sigma_ratio < options.min_sigma_ratio) {
    result.warnings.push_back(fmt::format(
        "{}: the residuals are {:.3g} times the stated sigmas (RMS over {} "
        "positions): the sigmas are stated far too large, or in another unit "
        "than the positions, and the navigation is weighted accordingly",
        what, *result.sigma_ratio, num_inliers));
  }
  return result;
}

nlohmann::json PlausibilityJson(const AlignmentPlausibility& plausibility) {
  return {{"median_range_m", plausibility.median_range_m
                                 ? nlohmann::json(*plausibility.median_range_m)
                                 : nlohmann::json()},
          {"num_depths", plausibility.num_depths},
          {"explained", plausibility.explained},
          {"sigma_ratio", plausibility.sigma_ratio
                              ? nlohmann::json(*plausibility.sigma_ratio)
                              : nlohmann::json()}};
}

std::string PlausibilityText(const AlignmentPlausibility& plausibility) {
  std::string text = "Plausibility: ";
  if (plausibility.median_range_m) {
    text += fmt::format(
        "cameras {:.3g} m from what they see (median of {} "
        "depths); ",
        *plausibility.median_range_m, plausibility.num_depths);
  }
  text += fmt::format(
      "the similarity explains {:.1f} % of the references' "
      "spread",
      100.0 * plausibility.explained);
  if (plausibility.sigma_ratio) {
    text += fmt::format("; residuals {:.3g} times the stated sigmas",
                        *plausibility.sigma_ratio);
  }
  return text + "\n";
}

std::vector<std::string> PlausibilityWarnings(
    const AlignmentPlausibility& plausibility,
    const AlignmentPlausibilityOptions& options, const std::string& flag) {
  if (!plausibility.errors.empty() && !options.accept_implausible) {
    std::string text;
    for (const std::string& error : plausibility.errors) {
      text += (text.empty() ? "" : "\n") + error;
    }
    throw ErrorAt(text, "\n(", flag, " 1 goes on regardless)");
  }
  std::vector<std::string> warnings;
  for (const std::string& error : plausibility.errors) {
    warnings.push_back(error + " (accepted: " + flag + " 1)");
  }
  warnings.insert(warnings.end(), plausibility.warnings.begin(),
                  plausibility.warnings.end());
  return warnings;
}

}  // namespace uw
