// What a similarity from a model onto navigation can tell about the
// navigation: gross mistakes that otherwise pass with normal-looking output
// (issue 17). A log in degrees read as metres aligns perfectly, at scale
// 1.6e-7 with residuals of 7e-7 "m"; images paired with the navigation of
// another time (a camera clock days off) align badly whatever the scale.
// Neither is a question of noise, so the checks are on what no survey can
// be: a camera that sees its scene from micrometres or kilometres away, a
// track the navigation does not follow, residuals a thousand times below the
// stated sigmas.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "colmap_plugins/align/similarity.h"
#include "colmap_plugins/scene/model.h"

namespace uw {

// Depths of every observed point in the cameras that see it, model units:
// how far the cameras are from what they map.
std::vector<double> ObservationDepths(const Reconstruction& model);

struct AlignmentPlausibilityOptions {
  // The median depth of the model's points in the cameras that see them,
  // after the similarity, m. No underwater camera maps what lies closer than
  // a few centimetres or farther than the water lets it see (tens of
  // metres): degrees as metres implies micrometres, millimetres as metres
  // hundreds of metres.
  double min_range_m = 0.05;
  double max_range_m = 100.0;
  // The similarity must explain at least this fraction of the references'
  // spread (1 − Σ|residual|² / Σ|reference − mean|² over the inliers).
  // Navigation of other times explains ~0, and so does a log whose noise
  // rivals a small survey: the stated sigmas tell them apart. Residuals
  // within max_sigma_ratio of them (RMS Mahalanobis per axis) are the
  // log's noise; beyond refuse_sigma_ratio (or with no sigmas stated) they
  // are an error; in between, a log noisier than it states is as likely as
  // a wrong pairing: a warning (--Nav.weight auto weights such a log).
  double min_explained = 0.5;
  double max_sigma_ratio = 3.0;
  double refuse_sigma_ratio = 10.0;
  // A robust similarity that calls most references outliers fitted the few
  // that happen to agree: at least this fraction must be inliers.
  double min_inlier_fraction = 0.5;
  // RMS Mahalanobis per axis below this: the sigmas are stated far too large
  // (or in other units than the positions). A warning: the adjustment then
  // weights the navigation too little, it is not wrong.
  double min_sigma_ratio = 1e-3;
  // The failed checks become warnings (a deliberate exotic survey).
  bool accept_implausible = false;

  void Check() const;
};

struct AlignmentPlausibility {
  // Median camera-to-point depth after the similarity, m; unset when the
  // model has no observed points.
  std::optional<double> median_range_m;
  size_t num_depths = 0;
  double explained = 0.0;
  // RMS over the inliers of Mahalanobis / sqrt(3); unset without
  // covariances.
  std::optional<double> sigma_ratio;
  // What cannot be (errors, unless accept_implausible) and what is suspect.
  std::vector<std::string> errors;
  std::vector<std::string> warnings;
};

// `model` in its own frame (before the similarity), `references` the
// targets paired with `similarity.residuals` (same order), `what` names the
// references in messages ("nav.csv").
AlignmentPlausibility CheckAlignmentPlausibility(
    const Reconstruction& model, const SimilarityResult& similarity,
    const std::vector<Eigen::Vector3d>& references, const std::string& what,
    const AlignmentPlausibilityOptions& options);

// The figures of `plausibility` as JSON (median_range_m, num_depths,
// explained, sigma_ratio; null when unknown) and as one line of text.
nlohmann::json PlausibilityJson(const AlignmentPlausibility& plausibility);
std::string PlausibilityText(const AlignmentPlausibility& plausibility);

// Throws uw::Error with every error of `plausibility` unless
// options.accept_implausible (whose flag is `flag`, named in the message);
// returns the warnings to report, the accepted errors among them.
std::vector<std::string> PlausibilityWarnings(
    const AlignmentPlausibility& plausibility,
    const AlignmentPlausibilityOptions& options, const std::string& flag);

}  // namespace uw
