// Bundle adjustment of a COLMAP model with navigation: the thesis's
// multiobjective BA (ch. 4 §5.2.1, Eq. 1-2) with per-dive offsets (§5.2.2)
// and soft rig constraints (ch. 6), on our COLMAP camera models.
//
// Cost (Eq. 2, generalised to full covariances and several prior kinds):
//   E = (1/M) sum rho(|r_v|^2)
//     + (lambda^2 sigma_n^2 / N) sum rho_n(|S_i (c_i - (p_i + delta_d))|^2)
//     + (lambda^2 sigma_n^2 / N) sum |S_a,i w_i|^2           (attitude)
//     + (lambda^2 sigma_n^2 / N) sum |S_delta delta_d|^2      (weak offsets)
//     + (sigma_v^2 / N_rig) sum |W e_rig|^2                   (rig)
// r_v: reprojection residual (px), M observations. c_i: camera centre, p_i
// its navigation position, S_i the whitening of its covariance, N priors.
// sigma_n^2 is the mean prior variance (trace / 3 averaged over priors), so
// that with isotropic equal priors the nav term is Eq. 2's
// (lambda^2 / N) sum |c_i - p_i|^2, lambda = sigma_v / sigma_n in px/m. The
// rig and attitude terms, stated in their own sigmas, enter the same way:
// in units of sigma, scaled to pixels by sigma_v = lambda sigma_n.
// That is NavWeighting::kThesis. The default, kLikelihood, drops the
// division by the numbers of terms (M, N, N_rig): the Gaussian likelihood
// when lambda is the true noise ratio (noise_levels.h estimates it).
//
// Gauge: with >= 3 non-collinear position priors the priors fix it; the
// reference dive's offset is zero. Without priors, 7 DOF are fixed as in
// COLMAP: the first image's pose and the largest translation coordinate of
// the second image (with a rig, only the first pose: rig baselines fix the
// scale).
#pragma once

#include <map>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "colmap_plugins/scene/model.h"

namespace uw {

enum class LossType { kTrivial, kHuber, kCauchy };

// How the objectives are weighted against each other (docs/uwcolmap.md,
// "Weighting"). Both take lambda = sigma_v / sigma_n:
//   kLikelihood: E = sum |r_v|^2 + lambda^2 sigma_n^2 sum |S_i e_i|^2 + ...,
//     the Gaussian likelihood when lambda is the true noise ratio;
//   kThesis: Eq. 2, each objective divided by its number of terms (M
//     reprojections, N priors), which weighs every prior M/N times more
//     than the likelihood does. Stiffer against systematic errors of the
//     images (doming from a wrong distortion), but it also writes the
//     navigation's noise into the model.
enum class NavWeighting { kLikelihood, kThesis };

// What a solve that reaches max_num_iterations still lowering its cost
// does (--BundleAdjustment.unconverged). An unconverged model is not what
// its covariance, its offsets or its scale describe; handed back with exit
// 0 it reads as a result (a multi-dive survey: 34 % off in scale, an
// offset 10 sigma off).
enum class UnconvergedPolicy {
  kContinue,  // solve on, max_num_iterations at a time, then fail
  kFail,      // an error at once: nothing written
  kWarn,      // keep the model, with a warning in the output and report
};
std::string UnconvergedPolicyName(UnconvergedPolicy policy);
UnconvergedPolicy UnconvergedPolicyFromName(const std::string& name);
std::string NavWeightingName(NavWeighting weighting);
NavWeighting NavWeightingFromName(const std::string& name);
std::string LossTypeName(LossType type);
LossType LossTypeFromName(const std::string& name);  // "none"/"trivial",
                                                     // "huber", "cauchy"

// A navigation prior on one image of the model.
struct ImagePosePrior {
  image_t image_id = 0;
  int dive = 1;
  Eigen::Vector3d position_in_world = Eigen::Vector3d::Zero();  // centre, m
  Eigen::Matrix3d position_covariance = Eigen::Matrix3d::Identity();  // m^2
  // Attitude prior and the covariance (rad^2) of the world-frame rotation
  // vector w with world_from_cam = Exp(w) * world_from_cam_prior.
  std::optional<Eigen::Quaterniond> cam_from_world_rotation;
  Eigen::Matrix3d rotation_covariance = Eigen::Matrix3d::Identity();
};

// One camera of a rig: its pose relative to the rig (= the reference
// camera) and the 1-sigma uncertainty of that pose.
struct SoftRigCamera {
  camera_t camera_id = 0;
  Rigid3d cam_from_rig;
  double rotation_sigma_rad = 0.0;
  double translation_sigma_m = 0.0;
};

struct SoftRig {
  camera_t reference_camera_id = 0;
  std::vector<SoftRigCamera> cameras;  // non-reference cameras
};

struct NavBundleAdjustmentOptions {
  // COLMAP's BundleAdjustment.* options (same meaning and defaults as
  // colmap 3.8's bundle_adjuster), but for the two below the tolerances.
  bool refine_focal_length = true;
  bool refine_principal_point = false;
  bool refine_extra_params = true;
  bool refine_extrinsics = true;
  int max_num_iterations = 100;
  UnconvergedPolicy unconverged = UnconvergedPolicy::kContinue;
  // kContinue: further solves of max_num_iterations before giving up (9:
  // 1000 iterations at colmap's 100, which a held-out multi-dive survey
  // needed where 100 stopped it 34 % off in scale).
  int max_continuations = 9;
  int max_linear_solver_iterations = 200;
  double gradient_tolerance = 0.0;
  double parameter_tolerance = 0.0;
  // Ceres' non-monotonic trust region (colmap: monotonic). Along a long
  // strip's weak bending the monotonic one crawls: on the scarp's 256-image
  // two-line plan every Gauss-Newton step won half of what it predicted,
  // 100 iterations left the cameras up to a metre from the minimum, and
  // 186 reached it; allowed to rise for a few steps, the same solve
  // reaches a lower cost in 18 (the vent, canyon and breakwater plans: the
  // same minimum in 3-4 times fewer iterations). docs/uwcolmap.md.
  bool use_nonmonotonic_steps = true;
  // colmap's 0 never stops a non-monotonic solve: at its minimum it keeps
  // taking steps that change the cost by rounding (1e-15 of it). 1e-12 is
  // far below what a step still on its way changes (1e-8 and more).
  double function_tolerance = 1e-12;
  LossType loss = LossType::kTrivial;  // on reprojection residuals
  double loss_scale_px = 1.0;
  int num_threads = -1;  // -1: all cores

  // Navigation. Without priors, the adjustment is plain BA.
  // lambda = sigma_v / sigma_n (px/m), Eq. 2.
  double weight_px_per_m = 1.0;
  NavWeighting weighting = NavWeighting::kLikelihood;
  bool use_attitude = false;
  LossType nav_loss = LossType::kTrivial;
  // In units of sigma: sqrt of chi^2(3 DOF, 95 %).
  double nav_loss_scale = 2.7955;

  // Per-dive offsets: one 3D offset per dive except the reference dive,
  // with a weak zero-mean prior of this sigma (m, per axis).
  bool dive_offsets = false;
  int reference_dive = 0;  // 0: the lowest dive number present
  double dive_offset_sigma_m = 10.0;

  // Soft rig: interpolate the rig pose at each camera's own time.
  bool rig_interpolate_time = true;
  // A rig image more than this long after its reference image gets no rig
  // term (the reference camera missed that frame).
  double rig_max_time_gap_s = 1.0;

  // Estimate the covariance of the dive offsets (and the prior residuals'
  // statistics) after the solve.
  bool estimate_offset_covariance = true;

  void Check() const;
};

struct DiveOffsetEstimate {
  int dive = 0;
  int num_images = 0;
  Eigen::Vector3d offset_in_world = Eigen::Vector3d::Zero();  // m
  std::optional<Eigen::Matrix3d> covariance;                  // m^2
};

struct PriorResidual {
  image_t image_id = 0;
  int dive = 0;
  // Camera centre minus (prior + dive offset), m, world frame.
  Eigen::Vector3d error_in_world = Eigen::Vector3d::Zero();
  double mahalanobis = 0.0;  // |S error| in sigmas
  std::optional<double> attitude_error_deg;
};

struct CostTerm {
  int num_residual_blocks = 0;
  double weighted_cost = 0.0;  // this term's share of Ceres' final cost
  // Mean squared residual before weighting: px^2 for reprojection (per
  // observation, |r|^2), m^2 for positions, rad^2 for attitudes,
  // sigma^2 for rigs and offsets.
  double mean_squared = 0.0;
};

struct NavBundleAdjustmentReport {
  double weight_px_per_m = 0.0;
  NavWeighting weighting = NavWeighting::kLikelihood;
  double nav_sigma_m = 0.0;  // sigma_n: RMS prior standard deviation
  int num_images = 0;
  int num_points = 0;
  int num_observations = 0;
  std::string gauge;
  std::map<std::string, CostTerm> initial_terms;
  std::map<std::string, CostTerm> final_terms;
  std::vector<DiveOffsetEstimate> dive_offsets;
  std::vector<PriorResidual> prior_residuals;
  int num_iterations = 0;
  // Solves of max_num_iterations after the first (UnconvergedPolicy).
  int num_continuations = 0;
  std::string termination;
  std::string solver;
  double solve_time_s = 0.0;
  double covariance_time_s = 0.0;
  std::string covariance_note;
  // What the result does not hold, printed and in ba_report.json: the
  // adjuster's (a solve stopped at its iteration limit) and the
  // controller's (a track the positions leave a rotation of, track_line.h;
  // images without scale transfer, scale_transfer.h).
  std::vector<std::string> warnings;
};

// Indices of a camera model's parameters that `options` keep constant
// (COLMAP's BundleAdjustment.refine_* flags).
std::vector<int> ConstantCameraParams(const NavBundleAdjustmentOptions& options,
                                      CameraModelId model_id);

// The RMS prior standard deviation sigma_n = sqrt(mean(trace(cov) / 3)), m
// (0 without priors).
double NavSigma(const std::vector<ImagePosePrior>& priors);

// The warning of a solve stopped at its iteration limit, whose last
// `last_iterations` lowered the cost from `earlier_cost` to `final_cost`.
// Levenberg-Marquardt crawls along a long survey's weak, curved directions
// (a strip's bending and scale): on the scarp plan without navigation,
// stopped at the limit of 100, the 86 iterations it still needed lowered
// the cost by 5e-6 of itself and moved the cameras by 1-2 m. COLMAP reports
// NO_CONVERGENCE and carries on; a model that far from its minimum is not
// what its covariance describes.
std::string NoConvergenceWarning(int max_num_iterations, int last_iterations,
                                 double earlier_cost, double final_cost);

// Adjusts `reconstruction` in place. Priors name images of the model
// (unknown ids throw uw::Error before anything changes). With a rig,
// `image_times` (seconds, one clock) must hold every image of the rig's
// cameras: a rig camera's image pairs with the last reference image taken
// at or before it, and with the motion between that image and the next (or,
// after a turn or at the end, the previous) reference image when
// rig_interpolate_time is set.
NavBundleAdjustmentReport AdjustWithNavigation(
    const NavBundleAdjustmentOptions& options,
    const std::vector<ImagePosePrior>& priors, const SoftRig* rig,
    const std::unordered_map<image_t, double>& image_times,
    Reconstruction* reconstruction);

}  // namespace uw
