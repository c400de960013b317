// The model's scale from all its laser images (ch4 spec §4.4-4.6): images
// are combined iteration by iteration of their Monte Carlos, weighted by
// the inverse of their variances, so that what they share (the one laser
// calibration, drawn alike in every image's iteration n) stays correlated
// and what they do not (features, spots) averages down. When the images
// disagree more than their uncertainties allow (Birge ratio R > 1: a scale
// that varies along the model, an unmodelled error) the interval is
// widened by R. Segments group images whose laser hits lie within a radius
// of each other (the thesis's 1 m), where the scale may be taken constant.
//
// Written by `laserscale estimate`: scale.json (the result `apply` reads),
// images.csv, items.csv, segments.csv, figures (PNG and SVG) and index.html.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "laserscale/scale_monte_carlo.h"

namespace uw {

struct ImageEstimate {
  std::string name;
  std::string problem;  // why there is no result (not localized, no spots)
  std::optional<ImageScaleResult> result;
  // Mean of the image's nominal laser hits (model frame), for segments.
  std::optional<Eigen::Vector3d> hit_centroid;
  std::string overlay;  // file name of its spot overlay in the report, if any
};

struct CombinedScale {
  std::vector<size_t> images;     // accepted images combined (indices)
  std::optional<double> nominal;  // weighted mean of their nominal scales
  SampleSummary monte_carlo;      // of the per-iteration weighted means
  std::vector<double> per_iteration;
  double birge_ratio = 1.0;
  double sigma = 0.0;  // Monte Carlo σ times max(1, R)
  double ci95_low = 0.0, ci95_high = 0.0;
  // Per source sampled alone in every member (ImageScaleResult::per_source),
  // the σ of the members combined with the same weights: its share of the
  // variance is (σ_source / monte_carlo.std_dev)^2. The shares sum to 1
  // where the sources act linearly and independently.
  std::vector<std::pair<ScaleSource, double>> source_sigmas;

  // (source_sigma / monte_carlo.std_dev)^2; 0 without any spread.
  double VarianceShare(double source_sigma) const;
};

// How the laser scale agrees with the navigation's own scale of a fused
// model (the covariance's gauge "priors"): the model is meant to be in
// metres (s = 1) within the navigation's scale uncertainty, the laser
// measures s within its own; |z| > 3 means one of them is wrong.
struct NavigationScaleCheck {
  double log_scale_sigma = 0.0;  // the navigation's (covariance draws)
  double z = 0.0;                // (s - 1) / sqrt(σ_s^2 + σ_nav^2)
  bool consistent = true;        // |z| <= 3
};

struct Segment {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  CombinedScale scale;
};

struct CombineOptions {
  double segment_radius = 1.0;  // model units
  void Check() const;
};

struct ModelScaleReport {
  ScaleMethod method = ScaleMethod::kFum;
  MonteCarloOptions monte_carlo;
  std::vector<ImageEstimate> images;
  CombinedScale model;
  std::vector<Segment> segments;
  // The covariance's draws the Monte Carlo used (0: the model taken as
  // exact), their gauge, and the check against the navigation's scale
  // (gauge "priors" only).
  int num_model_draws = 0;
  std::string model_gauge;
  std::optional<NavigationScaleCheck> navigation;
};

// The check of a combined scale against the navigation's scale σ; none
// without a scale, or when neither side has an uncertainty.
std::optional<NavigationScaleCheck> CheckAgainstNavigation(
    const CombinedScale& scale, double log_scale_sigma);

// Combines the accepted images. An empty combination (no accepted image)
// leaves model.nominal empty; the report then says why image by image.
ModelScaleReport CombineImages(std::vector<ImageEstimate> images,
                               ScaleMethod method,
                               const MonteCarloOptions& monte_carlo,
                               const CombineOptions& options);

std::string ScaleJsonText(const ModelScaleReport& report);
// Writes every file of the report into `dir` (created if needed); each
// file atomically.
void WriteScaleReport(const ModelScaleReport& report,
                      const std::filesystem::path& dir);

// What `apply` needs of a scale.json.
struct ScaleJson {
  double scale = 1.0;
  int num_model_draws = 0;  // 0: the model's own error was not sampled
  std::optional<NavigationScaleCheck> navigation;
};

// The scale s of a scale.json, checked: a combination exists and s is
// finite and positive. Throws uw::Error naming the file.
ScaleJson ReadScaleFromJson(const std::filesystem::path& path);

}  // namespace uw
