// The covariance of a bundle adjustment at its solution: the problem
// AdjustWithNavigation solves (reprojection, navigation position and
// attitude, dive offsets, soft rig; losses as Ceres applies them), each
// residual divided by its own sigma, through the Schur complement and the
// sparse inverse of schur_covariance.h. docs/covariance.md explains the
// gauge, the pixel sigma and the outputs.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

#include "colmap_plugins/ba/covariance_samples.h"
#include "colmap_plugins/ba/coverage_gaps.h"
#include "colmap_plugins/ba/nav_bundle_adjuster.h"
#include "colmap_plugins/ba/short_baselines.h"
#include "colmap_plugins/scene/model.h"

namespace uw {

// What fixes the 7 degrees of freedom (6 with a rig) that the images leave.
enum class CovarianceGauge {
  kPriors,       // the navigation priors (the fused model's own datum)
  kHeld,         // the adjuster's held coordinates without priors: the
                 // first image's pose and one translation coordinate of the
                 // second (COLMAP's choice)
  kFreeNetwork,  // inner constraints: the minimum-norm pseudo-inverse
                 // (minimum trace), what photogrammetry reports without
                 // control
};
std::string CovarianceGaugeName(CovarianceGauge gauge);  // priors, held,
                                                         // free_network
CovarianceGauge CovarianceGaugeFromName(const std::string& name);

// Who computes the marginals of the same problem.
enum class CovarianceMethod {
  kSchur,          // ours: Schur complement, one Cholesky, sparse inverse
  kCeresSparseQr,  // ceres::Covariance with SPARSE_QR: the peer it is
                   // timed against (bench/covariance_speed_bench.cc); no
                   // free network, co-visible blocks or draws
};
std::string CovarianceMethodName(CovarianceMethod method);  // schur,
                                                            // ceres_sparse_qr
CovarianceMethod CovarianceMethodFromName(const std::string& name);

struct BundleCovarianceOptions {
  CovarianceGauge gauge = CovarianceGauge::kPriors;
  CovarianceMethod method = CovarianceMethod::kSchur;
  // Pixel noise (px per coordinate); 0: estimated from the reprojection
  // residuals with the images' redundancy (2M - 3P - 6I - K + gauge).
  double pixel_sigma_px = 0.0;
  // The weight lambda (px/m) the adjustment gave the navigation priors
  // against the images (ba_report.json's weight_px_per_m): the priors'
  // sigmas are then taken as stated x pixel sigma / (lambda sigma_n), as
  // that adjustment weighted them (--Nav.weight auto: stated x s_n, the
  // factor the data show them off by). 0: as stated. bundle_adjuster sets
  // it to the weight it solved with.
  double nav_weight_px_per_m = 0.0;
  bool point_marginals = true;
  // Cross-covariances of image pairs that see a common point.
  bool covisible_cross = false;
  // Joint draws of the whole model's error (covariance_samples.h), for a
  // Monte Carlo downstream; 0: none. Memory and samples.bin grow as
  // num_samples x (12 bytes per point + 24 per image).
  int num_samples = 0;
  uint64_t sample_seed = 0;

  void Check() const;
};

// A pose's covariance as [world-frame rotation vector of world_from_cam
// (rad); camera centre in world (m)], world_from_cam = Exp(w) * estimate.
using PoseCovariance = Eigen::Matrix<double, 6, 6>;

struct ImageCovariance {
  image_t image_id = 0;
  bool held = false;  // part of the gauge: zero covariance by definition
  int num_points = 0;
  PoseCovariance rotation_center;
  Eigen::Matrix3d CenterCovariance() const {
    return rotation_center.bottomRightCorner<3, 3>();
  }
  Eigen::Matrix3d RotationCovariance() const {
    return rotation_center.topLeftCorner<3, 3>();
  }
};

struct CameraCovariance {
  camera_t camera_id = 0;
  std::vector<int> param_indices;  // the refined parameters, in order
  Eigen::MatrixXd params;          // their covariance
};

struct PointCovariance {
  point3D_t point3D_id = 0;
  int track_length = 0;
  Eigen::Matrix3d xyz;  // m^2, world
};

struct ImagePairCovariance {
  image_t image_id1 = 0;
  image_t image_id2 = 0;
  PoseCovariance rotation_center;  // rows image 1, columns image 2
};

struct BundleCovariance {
  CovarianceGauge gauge = CovarianceGauge::kPriors;
  CovarianceMethod method = CovarianceMethod::kSchur;
  std::string gauge_description;
  double pixel_sigma_px = 0.0;
  std::string pixel_sigma_source;
  // The factor on the priors' stated sigmas (1: as stated), and why.
  double nav_sigma_scale = 1.0;
  std::string nav_sigma_source;
  int num_observations = 0;
  std::vector<ImageCovariance> images;
  std::vector<CameraCovariance> cameras;
  std::map<int, Eigen::Matrix3d> dive_offsets;  // non-reference dives
  std::vector<PointCovariance> points;
  std::vector<ImagePairCovariance> covisible;
  // When num_samples > 0: the draws, their similarity removed.
  CovarianceSamples samples;
  // Where the points leave a hole inside the survey (plan view, from the
  // points' positions; coverage_gaps.h): no sigma can show it.
  CoverageGaps coverage_gaps;
  // Where every image that sees the points was taken from nearly the same
  // place (short_baselines.h): their depth is weak for that reason.
  ShortBaselines short_baselines;
  // Where the linearised covariance is not to be trusted (printed, and in
  // covariance.json): a focal length whose sigma exceeds
  // kPoorFocalLengthFraction of itself; coverage gaps; short baselines;
  // priors on a nearly straight track without attitude (track_line.h).
  std::vector<std::string> warnings;
  // From ComputeSchurCovariance.
  int num_residuals = 0;
  int num_reduced_coordinates = 0;
  long factor_nonzeros = 0;
  double reciprocal_condition = 0.0;
  double jacobian_time_s = 0.0;
  double schur_time_s = 0.0;
  double factor_time_s = 0.0;
  double inverse_time_s = 0.0;
  double total_time_s = 0.0;
};

// A self-calibration this uncertain about the focal length (sigma / f) is
// nearly degenerate (the focal length trades against the distance to the
// scene): the estimate's error is then dominated by nonlinearity and bias,
// which the linearised covariance does not describe.
constexpr double kPoorFocalLengthFraction = 0.05;

// The covariance of `model` under the adjustment `adjuster`, `priors`,
// `rig` and `image_times` define (the model is not changed; it should be
// the adjusted one). Throws uw::Error, naming the image, point or camera,
// for a problem without a covariance: an image seeing fewer than 3 points,
// a point seen once, non-finite parameters, a gauge that the options do not
// fix (kPriors without priors, kHeld or kFreeNetwork with them, kFreeNetwork
// with a rig), a rank-deficient problem.
BundleCovariance EstimateBundleCovariance(
    const NavBundleAdjustmentOptions& adjuster,
    const std::vector<ImagePosePrior>& priors, const SoftRig* rig,
    const std::unordered_map<image_t, double>& image_times,
    const Reconstruction& model, const BundleCovarianceOptions& options);

}  // namespace uw
