// The thesis's chapter-3 experiments on uwsim worlds (ch4 spec §14.1-14.2):
// a laser image is synthesised from the true mesh and pose (features are
// points of the surface seen through the camera, spots are where the beams'
// axes meet it), noise is added where a real survey has it (feature and
// spot pixels, the laser calibration), and the image goes through what a
// user's data goes through: localization against the model, ray casting on
// the model's mesh, the estimators, the Monte Carlo. The model is the world
// scaled by `model_scale`, so every estimate has a known answer, 1 /
// model_scale. This is how a user judges a laser set-up before a cruise
// (`laserscale simulate`).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "colmap_plugins/scene/model.h"
#include "common/mesh/ray_caster.h"
#include "laserscale/laser_setup.h"
#include "laserscale/scale_monte_carlo.h"

namespace uw {

// Standard deviations of what a laser image gets wrong.
struct ShotNoise {
  double feature_px = 0.0;  // σ_f, each feature coordinate
  double spot_px = 0.0;     // σ_l, each spot coordinate
  // The calibration a user has: each direction off by this angle
  // (isotropic), each origin by this much across Π per axis; reported as
  // its covariance.
  double direction_deg = 0.0;
  double origin_m = 0.0;

  void Check() const;
};

struct ShotOptions {
  int num_features = 1500;   // the thesis's count [L2328]
  double model_scale = 1.0;  // the model is the world times this
  ShotNoise noise;
  LocalizationOptions localization;

  void Check() const;
};

// One synthetic laser image, localized against the (scaled) model.
struct SyntheticShot {
  bool localized = false;
  std::string problem;  // why it is not
  LaserImage image;     // the localization's inliers, pose and RMS
  // The user's calibration (true set-up with errors and covariances).
  LaserSetup calibration;
  Rigid3d true_cam_from_world;  // in the model's frame
};

// `world_caster` casts on the true mesh (metres); the model's 3D points are
// its hits times model_scale. Spots whose beam misses, is occluded or
// leaves the image are absent. Deterministic for a seed.
SyntheticShot MakeSyntheticShot(const RayCaster& world_caster,
                                const Camera& camera,
                                const Rigid3d& cam_from_world,
                                const LaserSetup& truth,
                                const ShotOptions& options, uint64_t seed);

// The vent's rough flank (the views experiment's default "flank" area): the
// first surface met from (20, 3, 3) m looking along -x. Throws uw::Error if
// the world has no surface there.
Eigen::Vector3d VentFlankTarget(const RayCaster& world_caster);

// A mesh times `scale` (the model of a world).
TriangleMesh ScaledMesh(const TriangleMesh& mesh, double scale);

// The chapter-3 accuracy study: every view of a `views` survey at every
// distance, for every set-up, noise level and method, without Monte Carlo
// (the spread over views and trials is the accuracy).
struct ViewsExperimentOptions {
  std::string world = "vent";
  // The surveyed point: "flank" (vent only; the chimney's side 3 m above
  // the datum: the first surface met from (20, 3, 3) m looking along -x,
  // rough terrain like the thesis's area B), "top" (the views survey's own
  // point: the top of a vent, the floor of a seafloor; nearly flat at the
  // lasers' scale, like area A) or "custom" (`target`, world frame).
  std::string area = "flank";
  std::optional<Eigen::Vector3d> target;
  std::vector<double> distances_m = {2.0, 3.0, 4.0};
  std::vector<std::string> setups = {"A", "B", "C"};
  std::vector<ShotNoise> noise_levels = {ShotNoise()};
  std::vector<ScaleMethod> methods = {ScaleMethod::kFum, ScaleMethod::kPcm,
                                      ScaleMethod::kDirect,
                                      ScaleMethod::kDavisTusting};
  double model_scale = 1.0;
  int num_features = 1500;
  // Independent noise draws per view (1 for a noise-free study).
  int trials_per_view = 1;
  double max_angle_deg = 40.0;
  double step_deg = 5.0;
  uint64_t seed = 1;
  int num_threads = 0;

  void Check() const;
};

// Scale errors ε = s · model_scale − 1 of one (set-up, distance, noise,
// method) over all views and trials: per item (a laser, a pair) and per
// image (the mean of its items).
struct ErrorStats {
  size_t count = 0;
  size_t num_invalid = 0;  // items or images without a scale
  double mean = 0.0;
  double std_dev = 0.0;
  double max_abs = 0.0;
};
struct ViewsExperimentRow {
  std::string setup;
  double distance_m = 0.0;
  ShotNoise noise;
  ScaleMethod method = ScaleMethod::kFum;
  size_t num_views = 0;
  size_t num_unlocalized = 0;
  ErrorStats items;
  ErrorStats images;
  // Per image: (pitch, roll) of the view (deg) and ε (NaN: none).
  std::vector<std::array<double, 3>> image_errors;
};

using ExperimentProgress = std::function<void(size_t done, size_t total)>;

std::vector<ViewsExperimentRow> RunViewsExperiment(
    const ViewsExperimentOptions& options,
    const ExperimentProgress& progress = nullptr);

// The Monte Carlo's honesty (ch4 spec §14.2): `trials` independent noisy
// versions of one view, each localized and run through the Monte Carlo.
// A truthful Monte Carlo σ matches the spread of the trials' nominal
// estimates, and its 95 % interval covers the truth in ~95 % of trials.
struct CoverageResult {
  size_t num_trials = 0;             // with an image scale
  double spread_of_estimates = 0.0;  // σ of the nominal image scales
  double mean_monte_carlo_sigma = 0.0;
  double coverage_95 = 0.0;  // fraction of 2.5-97.5 % intervals with 1/k
  double coverage_68 = 0.0;  // same for 16-84 %
};
CoverageResult RunCoverageExperiment(
    const TriangleMesh& world_mesh, const Camera& camera,
    const Rigid3d& cam_from_world, const LaserSetup& truth,
    const ShotOptions& shot_options, ScaleMethod method,
    const MonteCarloOptions& monte_carlo, int trials, uint64_t seed);

}  // namespace uw
