// The scale of a model from one laser image, with its uncertainty by Monte
// Carlo (ch4 spec §4): each iteration re-samples the image's features with
// the localization's own noise level and re-localizes the image (from the
// nominal pose on the fixed inliers and 3D points, the spec's "cheaper
// option", equivalent for small noise: by default one Gauss-Newton step
// with the nominal Jacobian, LinearizedPose; or a full refinement), draws
// each spot
// from its covariance and each laser's direction and origin from the
// calibration's, and runs the whole chain: ray cast, estimator, scale. No
// distribution in between is approximated: the spread of the scales is the
// uncertainty.
//
// Iteration n of image i draws features and spots from SplitMix64 keyed by
// (seed, i, n), so a result is identical for any thread count and any split
// of the work. The calibration is drawn keyed by (seed, n) alone: every
// image sees the same calibration in iteration n, as every image of a
// survey shares the one calibration, so that combining images iteration by
// iteration (scale_report.h) keeps its error correlated instead of
// averaging it away.
//
// Scales are s = m / m̂ (multiply the model by s to get metres); the scale
// error of a model meant to be metric is s - 1.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "colmap_plugins/scene/model.h"
#include "common/mesh/ray_caster.h"
#include "laserscale/laser_setup.h"
#include "laserscale/localization.h"
#include "laserscale/scale_items.h"

namespace uw {

// A detected spot: its centre (COLMAP pixels) and the covariance of that
// centre (px^2), as the detector gives them.
struct Spot {
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
};

// What the model's own error does to one laser image, per joint draw of
// the bundle adjustment's posterior (laserscale/model_draws.h): one column
// per draw, iteration n of the Monte Carlo using draw n mod NumDraws() in
// every image, so that what images share (one camera, overlapping points)
// stays correlated when they are combined.
struct ImageModelDraws {
  // Deltas of the camera's refined parameters (rows: param_indices).
  std::vector<int> param_indices;
  Eigen::MatrixXd camera_deltas;
  // Deltas of the matches' points, 3 rows per match (zero for a point the
  // draws do not hold: num_points_without_draws).
  Eigen::MatrixXf point_deltas;
  int num_points_without_draws = 0;
  // How the surface under the laser hits moves, 3 rows: the mean delta of
  // the model points nearest the hits, the farthest of them this far away.
  Eigen::MatrixXf surface_shifts;
  double surface_radius = 0.0;
  // What of the model is not sampled (say, intrinsics held), for the user.
  std::string note;

  int NumDraws() const { return static_cast<int>(surface_shifts.cols()); }
};

// Everything one laser image contributes.
struct LaserImage {
  std::string name;
  Camera camera;
  // The localization's inliers and its result.
  std::vector<Correspondence2D3D> matches;
  Rigid3d cam_from_world;
  double feature_sigma_px = 0.0;  // the localization's RMS error
  // One per laser of the set-up; std::nullopt: not (confidently) detected.
  std::vector<std::optional<Spot>> spots;
  // The model's draws; none (NumDraws() == 0): the model is taken as exact.
  ImageModelDraws model;
};

// What a Monte Carlo can re-sample; each alone gives its share of the
// variance (EstimateLaserImages).
enum class ScaleSource { kFeatures, kSpots, kCalibration, kModel };
std::string ScaleSourceName(ScaleSource source);
constexpr ScaleSource kScaleSources[] = {
    ScaleSource::kFeatures, ScaleSource::kSpots, ScaleSource::kCalibration,
    ScaleSource::kModel};

struct MonteCarloOptions {
  int num_iterations = 5000;  // the thesis's N_MC
  uint64_t seed = 0;
  // What is re-sampled (all of it by default, as in the thesis).
  bool sample_features = true;
  bool sample_spots = true;
  bool sample_calibration = true;  // directions and origins
  // The model's intrinsics, points and surface, when the image has draws
  // (LaserImage::model): each draw's pose is refined to convergence in the
  // drawn model, the features' noise added to it by the linearization.
  bool sample_model = true;
  // false: the linearized re-localization (LinearizedPose, ~20x faster);
  // true: a refinement to convergence (RefinePose) every iteration. Both
  // give the same σ to < 1 % (scale_monte_carlo_test).
  bool exact_relocalization = false;
  int max_refine_iterations = 10;  // with exact_relocalization
  // The running mean and σ of the image's scale are recorded every this
  // many iterations (ch4 spec §4.3, the thesis's Fig. 19).
  int convergence_every = 50;
  // Acceptance (ch4 spec §4.5): at least this many lasers giving a scale
  // (detected, and their rays meeting the surface), and no item's nominal
  // scale further from the items' median than max_item_sigmas of its own
  // Monte Carlo σ (the scale is locally constant; a larger disagreement
  // than the spots and the calibration's stated uncertainty explain
  // betrays a calibration error [L2672]). That σ leaves the model's draws
  // out: they move every item of an image alike, so they cannot explain
  // items that disagree.
  int min_lasers = 2;
  double max_item_sigmas = 3.0;
  // Threads (<= 0: all cores). The result does not depend on it.
  int num_threads = 0;

  void Check() const;  // throws uw::Error naming the field

  bool Samples(ScaleSource source) const;
  // These options with only `source` sampled.
  MonteCarloOptions Only(ScaleSource source) const;
};

// Mean, σ (n - 1) and percentiles (linear interpolation) of valid samples.
struct SampleSummary {
  size_t num_samples = 0;  // valid ones
  double mean = 0.0;
  double std_dev = 0.0;
  double p2_5 = 0.0, p16 = 0.0, p50 = 0.0, p84 = 0.0, p97_5 = 0.0;
};
SampleSummary Summarize(std::vector<double> samples);

struct ItemResult {
  ScaleItem item;
  ItemScale nominal;  // from the nominal inputs
  SampleSummary monte_carlo;
  size_t num_invalid = 0;       // iterations without a scale
  std::string first_problem;    // the first such iteration's reason
  std::vector<double> samples;  // valid samples, in iteration order
};

struct ConvergencePoint {
  int iterations = 0;
  double mean = 0.0;
  double std_dev = 0.0;
};

struct ImageScaleResult {
  std::string image;
  ScaleMethod method = ScaleMethod::kFum;
  std::vector<ItemResult> items;
  // The image's scale: per iteration the mean of its items' valid scales
  // (so the shared pose's correlation is kept, ch4 spec §4.4).
  std::optional<double> nominal;
  SampleSummary monte_carlo;
  std::vector<double> samples;        // valid ones, in iteration order
  std::vector<double> per_iteration;  // one per iteration; NaN: none
  std::vector<ConvergencePoint> convergence;
  // Each sampled source alone (EstimateLaserImages): its per-iteration
  // scales, for the share of the combined variance it explains.
  std::vector<std::pair<ScaleSource, std::vector<double>>> per_source;
  int num_model_draws = 0;  // used; 0: the model taken as exact
  std::string model_note;   // ImageModelDraws::note
  bool accepted = false;
  std::string rejection;  // why not accepted
};

ImageScaleResult EstimateImageScale(const LaserImage& image, int image_index,
                                    const LaserSetup& setup,
                                    const RayCaster& caster, ScaleMethod method,
                                    const MonteCarloOptions& options);

}  // namespace uw
