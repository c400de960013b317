#include "colmap_plugins/ba/nav_bundle_adjuster.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <set>
#include <thread>
#include <unordered_set>

#include <ceres/ceres.h>
#include <fmt/format.h>
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include "colmap_plugins/ba/bundle_covariance.h"
#include "colmap_plugins/ba/ceres_covariance.h"
#include "colmap_plugins/ba/nav_prior.h"
#include "colmap_plugins/ba/prior_alignment.h"
#include "colmap_plugins/ba/reprojection_error.h"
#include "colmap_plugins/ba/rig_prior.h"
#include "colmap_plugins/ba/scale_transfer.h"
#include "colmap_plugins/ba/schur_covariance.h"
#include "colmap_plugins/ba/track_line.h"
#include "colmap_plugins/cameras/camera_models.h"
#include "common/util/error.h"

namespace uw {

std::string LossTypeName(LossType type) {
  switch (type) {
    case LossType::kTrivial:
      return "none";
    case LossType::kHuber:
      return "huber";
    case LossType::kCauchy:
      return "cauchy";
  }
  return "?";
}

LossType LossTypeFromName(const std::string& name) {
  if (name == "none" || name == "trivial" || name == "TRIVIAL") {
    return LossType::kTrivial;
  }
  if (name == "huber" || name == "HUBER") return LossType::kHuber;
  if (name == "cauchy" || name == "CAUCHY") return LossType::kCauchy;
  throw ErrorAt("unknown loss '", name, "' (none, huber or cauchy)");
}

std::string NavWeightingName(NavWeighting weighting) {
  return weighting == NavWeighting::kThesis ? "thesis" : "likelihood";
}

NavWeighting NavWeightingFromName(const std::string& name) {
  if (name == "likelihood") return NavWeighting::kLikelihood;
  if (name == "thesis") return NavWeighting::kThesis;
  throw ErrorAt("unknown navigation weighting '", name,
                "' (likelihood or thesis)");
}

void NavBundleAdjustmentOptions::Check() const {
  const auto positive = [](double value, const char* name) {
    if (!(std::isfinite(value) && value > 0.0)) {
      throw ErrorAt("bundle adjustment option ", name, " = ", value,
                    " must be positive");
    }
  };
  positive(loss_scale_px, "loss_scale_px");
  positive(weight_px_per_m, "weight_px_per_m");
  positive(nav_loss_scale, "nav_loss_scale");
  positive(dive_offset_sigma_m, "dive_offset_sigma_m");
  positive(rig_max_time_gap_s, "rig_max_time_gap_s");
  if (max_num_iterations < 0 || max_linear_solver_iterations < 1) {
    throw ErrorAt("bundle adjustment iteration limits must be >= 0 / >= 1");
  }
  if (max_continuations < 0) {
    throw ErrorAt("bundle adjustment max_continuations must be >= 0, got ",
                  max_continuations);
  }
  for (const double tolerance :
       {function_tolerance, gradient_tolerance, parameter_tolerance}) {
    if (!(std::isfinite(tolerance) && tolerance >= 0.0)) {
      throw ErrorAt("bundle adjustment tolerances must be >= 0");
    }
  }
}

std::vector<int> ConstantCameraParams(const NavBundleAdjustmentOptions& options,
                                      CameraModelId model_id) {
  std::vector<int> constant;
  VisitCameraModel(model_id, [&](auto tag) {
    using Model = typename decltype(tag)::type;
    if (!options.refine_focal_length) {
      constant.insert(constant.end(), Model::kFocalLengthIdxs.begin(),
                      Model::kFocalLengthIdxs.end());
    }
    if (!options.refine_principal_point) {
      constant.insert(constant.end(), Model::kPrincipalPointIdxs.begin(),
                      Model::kPrincipalPointIdxs.end());
    }
    if (!options.refine_extra_params) {
      constant.insert(constant.end(), Model::kExtraParamsIdxs.begin(),
                      Model::kExtraParamsIdxs.end());
    }
  });
  return constant;
}

double NavSigma(const std::vector<ImagePosePrior>& priors) {
  if (priors.empty()) return 0.0;
  double sum = 0.0;
  for (const ImagePosePrior& prior : priors) {
    sum += prior.position_covariance.trace() / 3.0;
  }
  return std::sqrt(sum / priors.size());
}

std::string UnconvergedPolicyName(UnconvergedPolicy policy) {
  switch (policy) {
    case UnconvergedPolicy::kContinue:
      return "continue";
    case UnconvergedPolicy::kFail:
      return "fail";
    case UnconvergedPolicy::kWarn:
      return "warn";
  }
  throw ErrorAt("invalid UnconvergedPolicy ", static_cast<int>(policy));
}

UnconvergedPolicy UnconvergedPolicyFromName(const std::string& name) {
  for (const UnconvergedPolicy policy :
       {UnconvergedPolicy::kContinue, UnconvergedPolicy::kFail,
        UnconvergedPolicy::kWarn}) {
    if (name == UnconvergedPolicyName(policy)) return policy;
  }
  throw ErrorAt("unknown unconverged policy '", name,
                "' (continue, fail or warn)");
}

std::string NoConvergenceWarning(int max_num_iterations, int last_iterations,
                                 double earlier_cost, double final_cost) {
  // A final cost of 0 (exact data) has no relative decrease to give.
  const std::string decrease =
      final_cost > 0.0
          ? fmt::format("{:.2g} times its final value",
                        (earlier_cost - final_cost) / final_cost)
          : fmt::format("{:.2g} to a final cost of 0", earlier_cost);
  return fmt::format(
      "the adjustment stopped at its iteration limit "
      "(--BundleAdjustment.max_num_iterations {}) before converging: its "
      "last {} iterations still lowered the cost by {}. Along its weakest "
      "directions the model may still be far from the minimum (a 100 m "
      "single pass without navigation: 1-2 m), and its covariance describes "
      "the minimum, not this model. Raise "
      "--BundleAdjustment.max_num_iterations",
      max_num_iterations, last_iterations, decrease);
}

namespace {

// The warning above from a solve's summary: the decrease over its last 10
// iterations.
std::string IterationLimitWarning(const ceres::Solver::Summary& summary,
                                  int max_num_iterations) {
  constexpr int kLastIterations = 10;
  const std::vector<ceres::IterationSummary>& iterations = summary.iterations;
  const int last = std::max(
      0,
      std::min<int>(kLastIterations, static_cast<int>(iterations.size()) - 1));
  const double earlier = iterations.empty()
                             ? summary.final_cost
                             : iterations[iterations.size() - 1 - last].cost;
  return NoConvergenceWarning(max_num_iterations, last, earlier,
                              summary.final_cost);
}

using Clock = std::chrono::steady_clock;

struct PoseBlock {
  double rotation[4];  // cam_from_world, w x y z
  double translation[3];
};

ceres::LossFunction* MakeLoss(LossType type, double scale) {
  switch (type) {
    case LossType::kTrivial:
      return nullptr;
    case LossType::kHuber:
      return new ceres::HuberLoss(scale);
    case LossType::kCauchy:
      return new ceres::CauchyLoss(scale);
  }
  return nullptr;
}

// Weights of each objective: what multiplies each residual kind. The
// solve uses the thesis's normalised weights; the covariance uses the
// statistical ones (every residual divided by its own sigma).
struct Weights {
  double reprojection = 1.0;  // per px
  double nav = 1.0;           // per sigma of a prior
  double rig = 1.0;           // per sigma of a rig constraint
  double reprojection_loss_scale = 1.0;
  double nav_loss_scale = 1.0;
};

// A rig term: the rig camera's image, its reference image(s), alpha.
struct RigPairing {
  size_t cam_index = 0;
  size_t a_index = 0;
  std::optional<size_t> b_index;
  double alpha = 0.0;
  const SoftRigCamera* camera = nullptr;
};

// The parameter blocks of a model being adjusted, and the terms to add.
class Adjustment {
 public:
  Adjustment(const NavBundleAdjustmentOptions& options,
             const std::vector<ImagePosePrior>& priors, const SoftRig* rig,
             const std::unordered_map<image_t, double>& image_times,
             Reconstruction* reconstruction);

  NavBundleAdjustmentReport Run();
  // The covariance at the current parameters (bundle_covariance.h).
  BundleCovariance Covariance(const BundleCovarianceOptions& options);
  // The engine's tangent draws as the model's deltas, similarity removed.
  CovarianceSamples ConvertSamples(
      const SchurCovariance& covariance,
      const std::vector<size_t>& camera_variables,
      const std::vector<Eigen::MatrixXd>& embeddings,
      const std::vector<point3D_t>& point_ids,
      const std::vector<CameraCovariance>& cameras) const;

 private:
  void IndexAndValidate();
  void PairRigImages(const std::unordered_map<image_t, double>& image_times);
  std::string ChooseGauge();
  // Builds every residual block with `weights` into `problem`; records the
  // blocks of each term in `terms` when given.
  void Build(const Weights& weights, ceres::Problem* problem,
             std::map<std::string, std::vector<ceres::ResidualBlockId>>* terms);
  void SetManifoldsAndConstants(ceres::Problem* problem);
  std::map<std::string, CostTerm> EvaluateTerms(
      const Weights& weights, ceres::Problem* problem,
      const std::map<std::string, std::vector<ceres::ResidualBlockId>>& terms)
      const;
  // Whether the placement rounds of Run apply: plain position priors and
  // nothing else that sees the model's placement.
  bool PlacementApplies() const;
  // options_.num_threads, every core when it is not > 0.
  int NumThreads() const {
    return options_.num_threads > 0
               ? options_.num_threads
               : static_cast<int>(
                     std::max(1u, std::thread::hardware_concurrency()));
  }
  // Sum over observations of |reprojection error|^2, px^2.
  double SumSquaredReprojection() const;
  // 2M minus the parameters the images determine (all but a similarity, a
  // rigid motion with a rig): the reprojection residuals' degrees of
  // freedom.
  long ReprojectionRedundancy() const;
  // Moves the model by the similarity that minimises the position priors'
  // term for its current shape; false when that similarity is the identity
  // (to rounding).
  // With dive offsets, also sets them to the joint fit's.
  bool ReplaceOnPriors();
  // Camera centres of the priors' images, in the priors' order.
  std::vector<Eigen::Vector3d> PriorCentres() const;
  // Dive offsets from where the model is, before the first solve (they
  // start at zero): the joint fit with the placement when the placement
  // rounds apply, else each dive's mean residual.
  void SeedDiveOffsets();
  void EstimateOffsetCovariance(NavBundleAdjustmentReport* report);
  // Images (indices into poses_) whose pose the images do not fix, and
  // the points that leaves with fewer than two images, in turn until none
  // is left: an image seeing fewer than 3 points that 2 of the others see.
  struct UndeterminedByImages {
    std::vector<size_t> images;
    std::vector<point3D_t> points;
  };
  UndeterminedByImages FindUndeterminedByImages() const;
  // Checks that `gauge` is one this problem can have and fixes it; returns
  // its description.
  std::string ChooseCovarianceGauge(CovarianceGauge gauge);
  // The pixel sigma of the covariance: given, or from the residuals.
  void ChoosePixelSigma(const BundleCovarianceOptions& options,
                        BundleCovariance* covariance) const;
  // The factor on the priors' stated sigmas: 1, or as the adjustment
  // weighted them (BundleCovarianceOptions::nav_weight_px_per_m).
  void ChooseNavSigmaScale(const BundleCovarianceOptions& options,
                           BundleCovariance* covariance) const;
  // The similarity directions in the tangent space of each variable.
  void FillSimilarityNullSpace(const ceres::Problem& problem,
                               const std::vector<point3D_t>& point_ids,
                               SchurCovarianceOptions* options) const;
  void FillPriorResiduals(NavBundleAdjustmentReport* report) const;
  void CopyBack() const;

  const NavBundleAdjustmentOptions& options_;
  const std::vector<ImagePosePrior>& priors_;
  const SoftRig* rig_;
  Reconstruction* reconstruction_;

  std::vector<PoseBlock> poses_;
  std::unordered_map<image_t, size_t> image_index_;
  std::unordered_map<point3D_t, Eigen::Vector3d> points_;
  std::vector<std::vector<double>> camera_params_;
  std::unordered_map<camera_t, size_t> camera_index_;
  std::map<int, Eigen::Vector3d> dive_offsets_;
  int reference_dive_ = 0;
  std::vector<RigPairing> rig_pairings_;
  size_t num_observations_ = 0;
  double nav_sigma_m_ = 0.0;
  double pixel_sigma_ = 1.0;

  // Gauge without priors.
  std::optional<size_t> fixed_pose_;
  std::optional<std::pair<size_t, int>> fixed_translation_coordinate_;
};

Adjustment::Adjustment(const NavBundleAdjustmentOptions& options,
                       const std::vector<ImagePosePrior>& priors,
                       const SoftRig* rig,
                       const std::unordered_map<image_t, double>& image_times,
                       Reconstruction* reconstruction)
    : options_(options),
      priors_(priors),
      rig_(rig),
      reconstruction_(reconstruction) {
  options_.Check();
  IndexAndValidate();
  if (rig_ != nullptr) PairRigImages(image_times);
}

void Adjustment::IndexAndValidate() {
  const std::vector<Image>& images = reconstruction_->Images();
  poses_.resize(images.size());
  for (size_t i = 0; i < images.size(); ++i) {
    const Image& image = images[i];
    image_index_[image.image_id] = i;
    const Eigen::Quaterniond q = image.cam_from_world.rotation.normalized();
    poses_[i] = {{q.w(), q.x(), q.y(), q.z()},
                 {image.cam_from_world.translation.x(),
                  image.cam_from_world.translation.y(),
                  image.cam_from_world.translation.z()}};
    if (!image.cam_from_world.translation.allFinite() ||
        !image.cam_from_world.rotation.coeffs().allFinite()) {
      throw ErrorAt("image ", image.image_id, " (", image.name,
                    ") has a non-finite pose");
    }
  }
  for (size_t c = 0; c < reconstruction_->Cameras().size(); ++c) {
    const Camera& camera = reconstruction_->Cameras()[c];
    camera_index_[camera.camera_id] = c;
    camera_params_.push_back(camera.params);
  }
  for (const Point3D& point : reconstruction_->Points3D()) {
    points_[point.point3D_id] = point.xyz;
  }
  for (const Image& image : images) {
    for (const Point2D& point2D : image.points2D) {
      if (point2D.HasPoint3D()) ++num_observations_;
    }
  }
  for (const Frame& frame : reconstruction_->Frames()) {
    if (frame.data_ids.size() > 1) {
      throw ErrorAt("frame ", frame.frame_id,
                    " holds several images; models with multi-camera "
                    "frames are not supported yet (give the rig as rig.json "
                    "on a model without frames)");
    }
  }
  if (num_observations_ == 0) {
    throw ErrorAt("the model has no observations of 3D points");
  }

  std::set<image_t> seen;
  std::set<int> dives;
  for (const ImagePosePrior& prior : priors_) {
    if (image_index_.count(prior.image_id) == 0) {
      throw ErrorAt("a prior names image id ", prior.image_id,
                    ", which is not in the model");
    }
    if (!seen.insert(prior.image_id).second) {
      throw ErrorAt("image id ", prior.image_id, " has two priors");
    }
    if (!prior.position_in_world.allFinite()) {
      throw ErrorAt("the prior of image id ", prior.image_id,
                    " has a non-finite position");
    }
    try {
      SqrtInformation(prior.position_covariance);
      if (options_.use_attitude && prior.cam_from_world_rotation) {
        SqrtInformation(prior.rotation_covariance);
      }
    } catch (const Error& error) {
      throw ErrorAt("the prior of image id ", prior.image_id, ": ",
                    error.what());
    }
    dives.insert(prior.dive);
  }
  if (!priors_.empty()) {
    nav_sigma_m_ = NavSigma(priors_);
    pixel_sigma_ = options_.weight_px_per_m * nav_sigma_m_;
    reference_dive_ =
        options_.reference_dive != 0 ? options_.reference_dive : *dives.begin();
    if (options_.dive_offsets && dives.count(reference_dive_) == 0) {
      throw ErrorAt("reference dive ", reference_dive_, " has no priors");
    }
    for (const int dive : dives) {
      dive_offsets_[dive] = Eigen::Vector3d::Zero();
    }
  }
  if (rig_ != nullptr) {
    if (camera_index_.count(rig_->reference_camera_id) == 0) {
      throw ErrorAt("the rig's reference camera ", rig_->reference_camera_id,
                    " is not in the model");
    }
    for (const SoftRigCamera& camera : rig_->cameras) {
      if (camera_index_.count(camera.camera_id) == 0) {
        throw ErrorAt("the rig names camera ", camera.camera_id,
                      ", which is not in the model");
      }
      if (!(camera.rotation_sigma_rad > 0.0 &&
            camera.translation_sigma_m > 0.0)) {
        throw ErrorAt("rig camera ", camera.camera_id,
                      " needs positive rotation and translation sigmas");
      }
    }
  }
}

void Adjustment::PairRigImages(
    const std::unordered_map<image_t, double>& image_times) {
  const std::vector<Image>& images = reconstruction_->Images();
  const auto time_of = [&](const Image& image) {
    const auto it = image_times.find(image.image_id);
    if (it == image_times.end()) {
      throw ErrorAt("rig image ", image.name,
                    " has no time (give image times for rigs)");
    }
    return it->second;
  };
  // Reference images in time order.
  std::vector<std::pair<double, size_t>> reference;
  for (size_t i = 0; i < images.size(); ++i) {
    if (images[i].camera_id == rig_->reference_camera_id) {
      reference.emplace_back(time_of(images[i]), i);
    }
  }
  std::sort(reference.begin(), reference.end());
  const auto center = [&](size_t i) { return images[i].ProjectionCenter(); };
  for (size_t i = 0; i < images.size(); ++i) {
    const auto camera =
        std::find_if(rig_->cameras.begin(), rig_->cameras.end(),
                     [&](const SoftRigCamera& c) {
                       return c.camera_id == images[i].camera_id;
                     });
    if (camera == rig_->cameras.end()) continue;
    const double t = time_of(images[i]);
    auto after =
        std::upper_bound(reference.begin(), reference.end(), t,
                         [](double value, const std::pair<double, size_t>& r) {
                           return value < r.first;
                         });
    if (after == reference.begin()) continue;
    const auto a = std::prev(after);
    if (t - a->first > options_.rig_max_time_gap_s) continue;
    RigPairing pairing;
    pairing.cam_index = i;
    pairing.camera = &*camera;
    pairing.a_index = a->second;
    if (options_.rig_interpolate_time) {
      // The motion from a to the next reference image b, unless a ends a
      // straight run (a line of a lawnmower): then a -> b is a turn, unlike
      // both the segment before a and the one after b, and the motion at a
      // is the one that led to a.
      const bool has_next = after != reference.end();
      const bool has_previous = a != reference.begin();
      const bool has_next2 = has_next && std::next(after) != reference.end();
      const auto agree = [&](size_t p, size_t q, size_t r) {
        const Eigen::Vector3d first = center(q) - center(p);
        const Eigen::Vector3d second = center(r) - center(q);
        return first.dot(second) >= 0.5 * first.norm() * second.norm();
      };
      bool use_next = has_next;
      if (has_next && has_previous) {
        use_next = agree(std::prev(a)->second, a->second, after->second) ||
                   (has_next2 &&
                    agree(a->second, after->second, std::next(after)->second));
      }
      if (use_next) {
        pairing.b_index = after->second;
        pairing.alpha = (t - a->first) / (after->first - a->first);
      } else if (has_previous) {
        const auto p = std::prev(a);
        pairing.b_index = a->second;
        pairing.a_index = p->second;
        pairing.alpha = (t - p->first) / (a->first - p->first);
      }
    }
    rig_pairings_.push_back(pairing);
  }
}

std::string Adjustment::ChooseGauge() {
  if (!priors_.empty()) {
    if (priors_.size() < 3) {
      throw ErrorAt("navigation priors need at least 3 images; got ",
                    priors_.size());
    }
    Eigen::MatrixXd centered(3, priors_.size());
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const ImagePosePrior& prior : priors_) mean += prior.position_in_world;
    mean /= priors_.size();
    for (size_t i = 0; i < priors_.size(); ++i) {
      centered.col(i) = priors_[i].position_in_world - mean;
    }
    const Eigen::Vector3d singular =
        Eigen::JacobiSVD<Eigen::MatrixXd>(centered).singularValues();
    // The spread across the line of the priors must exceed their noise, or
    // the rotation about that line is left to the noise.
    const double across = singular(1) / std::sqrt(priors_.size());
    if (!(across > 0.1 * nav_sigma_m_ && singular(1) > 1e-6 * singular(0))) {
      throw ErrorAt(
          "the ", priors_.size(),
          " navigation priors are (nearly) collinear: RMS spread across "
          "their line ",
          across, " m vs prior sigma ", nav_sigma_m_,
          " m; the rotation about that line is not determined");
    }
    return "navigation priors";
  }
  if (poses_.size() < 2) {
    throw ErrorAt("bundle adjustment needs at least 2 images");
  }
  fixed_pose_ = 0;
  if (rig_ != nullptr && !rig_pairings_.empty()) {
    return "first image pose (rig baselines fix the scale)";
  }
  // Scaling about the first camera moves the second one's translation by
  // -R_2 (c_2 - c_1); its largest coordinate is the one that pins the scale
  // (COLMAP always fixes x, which does not when the baseline lies along
  // the second camera's y or z axis).
  const Image& first = reconstruction_->Images()[0];
  const Image& second = reconstruction_->Images()[1];
  const Eigen::Vector3d scale_direction =
      second.cam_from_world.RotationMatrix() *
      (second.ProjectionCenter() - first.ProjectionCenter());
  int largest = 0;
  scale_direction.cwiseAbs().maxCoeff(&largest);
  fixed_translation_coordinate_ = std::make_pair(size_t{1}, largest);
  return "first image pose + second image translation coordinate " +
         std::to_string(largest);
}

void Adjustment::Build(
    const Weights& weights, ceres::Problem* problem,
    std::map<std::string, std::vector<ceres::ResidualBlockId>>* terms) {
  const auto record = [&](const char* term, ceres::ResidualBlockId id) {
    if (terms != nullptr) (*terms)[term].push_back(id);
  };
  const std::vector<Image>& images = reconstruction_->Images();
  std::vector<PoseBlock>& poses = poses_;
  std::map<int, Eigen::Vector3d>& offsets = dive_offsets_;

  // Point by point: Ceres looks every block of a residual up in a map
  // keyed by address, and the residuals of one point after another keep
  // that lookup in cache (image by image, it took 3.7 s at 2000 images).
  for (const Point3D& point : reconstruction_->Points3D()) {
    double* xyz = points_.at(point.point3D_id).data();
    for (const TrackElement& element : point.track) {
      const size_t i = image_index_.at(element.image_id);
      const Image& image = images[i];
      const size_t c = camera_index_.at(image.camera_id);
      ceres::CostFunction* cost = VisitCameraModel(
          reconstruction_->Cameras()[c].model_id,
          [&](auto tag) -> ceres::CostFunction* {
            using Model = typename decltype(tag)::type;
            return ReprojectionErrorCostFunctor<Model>::Create(
                image.points2D[element.point2D_idx].xy, weights.reprojection);
          });
      record("reprojection",
             problem->AddResidualBlock(
                 cost, MakeLoss(options_.loss, weights.reprojection_loss_scale),
                 poses[i].rotation, poses[i].translation, xyz,
                 camera_params_[c].data()));
    }
  }

  for (const ImagePosePrior& prior : priors_) {
    PoseBlock& pose = poses[image_index_.at(prior.image_id)];
    const int dive = options_.dive_offsets ? prior.dive : reference_dive_;
    record("navigation_position",
           problem->AddResidualBlock(
               PositionPriorCostFunctor::Create(
                   prior.position_in_world,
                   weights.nav * SqrtInformation(prior.position_covariance)),
               MakeLoss(options_.nav_loss, weights.nav_loss_scale),
               pose.rotation, pose.translation, offsets.at(dive).data()));
    if (options_.use_attitude && prior.cam_from_world_rotation) {
      record("navigation_attitude",
             problem->AddResidualBlock(
                 AttitudePriorCostFunctor::Create(
                     *prior.cam_from_world_rotation,
                     weights.nav * SqrtInformation(prior.rotation_covariance)),
                 MakeLoss(options_.nav_loss, weights.nav_loss_scale),
                 pose.rotation));
    }
  }
  if (options_.dive_offsets) {
    for (auto& [dive, offset] : offsets) {
      if (dive == reference_dive_) continue;
      record("dive_offset_prior",
             problem->AddResidualBlock(
                 DiveOffsetPriorCostFunctor::Create(
                     weights.nav / options_.dive_offset_sigma_m *
                     Eigen::Matrix3d::Identity()),
                 nullptr, offset.data()));
    }
  }

  for (const RigPairing& pairing : rig_pairings_) {
    const SoftRigCamera& camera = *pairing.camera;
    RigCameraPrior prior;
    prior.cam_from_rig = camera.cam_from_rig.rotation.normalized();
    prior.cam_center_in_rig = camera.cam_from_rig.Inverse().translation;
    prior.rotation_weight = weights.rig / camera.rotation_sigma_rad;
    prior.translation_weight = weights.rig / camera.translation_sigma_m;
    PoseBlock& cam = poses[pairing.cam_index];
    PoseBlock& a = poses[pairing.a_index];
    if (pairing.b_index) {
      PoseBlock& b = poses[*pairing.b_index];
      record("rig",
             problem->AddResidualBlock(
                 InterpolatedRigPriorCostFunctor::Create(prior, pairing.alpha),
                 nullptr, a.rotation, a.translation, b.rotation, b.translation,
                 cam.rotation, cam.translation));
    } else {
      record("rig", problem->AddResidualBlock(
                        RigPriorCostFunctor::Create(prior), nullptr, a.rotation,
                        a.translation, cam.rotation, cam.translation));
    }
  }
  SetManifoldsAndConstants(problem);
}

void Adjustment::SetManifoldsAndConstants(ceres::Problem* problem) {
  std::vector<PoseBlock>& poses = poses_;
  for (size_t i = 0; i < poses.size(); ++i) {
    if (!problem->HasParameterBlock(poses[i].rotation)) continue;
    problem->SetManifold(poses[i].rotation, new ceres::QuaternionManifold);
    if (!options_.refine_extrinsics || fixed_pose_ == i) {
      problem->SetParameterBlockConstant(poses[i].rotation);
      problem->SetParameterBlockConstant(poses[i].translation);
    } else if (fixed_translation_coordinate_ &&
               fixed_translation_coordinate_->first == i) {
      problem->SetManifold(poses[i].translation,
                           new ceres::SubsetManifold(
                               3, {fixed_translation_coordinate_->second}));
    }
  }
  for (size_t c = 0; c < camera_params_.size(); ++c) {
    double* params = camera_params_[c].data();
    if (!problem->HasParameterBlock(params)) continue;
    const std::vector<int> constant =
        ConstantCameraParams(options_, reconstruction_->Cameras()[c].model_id);
    if (constant.size() == camera_params_[c].size()) {
      problem->SetParameterBlockConstant(params);
    } else if (!constant.empty()) {
      problem->SetManifold(
          params, new ceres::SubsetManifold(
                      static_cast<int>(camera_params_[c].size()), constant));
    }
  }
  const auto reference = dive_offsets_.find(reference_dive_);
  if (reference != dive_offsets_.end() &&
      problem->HasParameterBlock(reference->second.data())) {
    problem->SetParameterBlockConstant(reference->second.data());
  }
}

std::map<std::string, CostTerm> Adjustment::EvaluateTerms(
    const Weights& weights, ceres::Problem* problem,
    const std::map<std::string, std::vector<ceres::ResidualBlockId>>& terms)
    const {
  std::map<std::string, CostTerm> result;
  for (const auto& [name, blocks] : terms) {
    ceres::Problem::EvaluateOptions evaluate;
    evaluate.residual_blocks = blocks;
    evaluate.apply_loss_function = true;
    double cost = 0.0;
    problem->Evaluate(evaluate, &cost, nullptr, nullptr, nullptr);
    CostTerm& term = result[name];
    term.num_residual_blocks = static_cast<int>(blocks.size());
    term.weighted_cost = cost;
    // Rig and offset residuals are in sigmas times one scalar weight and
    // carry no loss: their mean square in sigma^2 follows from the cost.
    const double scalar_weight = name == "rig"                 ? weights.rig
                                 : name == "dive_offset_prior" ? weights.nav
                                                               : 0.0;
    if (scalar_weight > 0.0 && !blocks.empty()) {
      term.mean_squared =
          2.0 * cost /
          (scalar_weight * scalar_weight * static_cast<double>(blocks.size()));
    }
  }
  // Unweighted mean squares, from the parameter values directly.
  if (result.count("reprojection") != 0) {
    result["reprojection"].mean_squared =
        SumSquaredReprojection() / num_observations_;
  }
  if (result.count("navigation_position") != 0) {
    double sum = 0.0;
    for (const ImagePosePrior& prior : priors_) {
      const PoseBlock& pose = poses_[image_index_.at(prior.image_id)];
      const int dive = options_.dive_offsets ? prior.dive : reference_dive_;
      Eigen::Vector3d residual;
      PositionPriorCostFunctor(prior.position_in_world,
                               Eigen::Matrix3d::Identity())(
          pose.rotation, pose.translation, dive_offsets_.at(dive).data(),
          residual.data());
      sum += residual.squaredNorm();
    }
    result["navigation_position"].mean_squared = sum / priors_.size();
  }
  if (result.count("navigation_attitude") != 0) {
    double sum = 0.0;
    for (const ImagePosePrior& prior : priors_) {
      if (!prior.cam_from_world_rotation) continue;
      Eigen::Vector3d residual;
      AttitudePriorCostFunctor(*prior.cam_from_world_rotation,
                               Eigen::Matrix3d::Identity())(
          poses_[image_index_.at(prior.image_id)].rotation, residual.data());
      sum += residual.squaredNorm();
    }
    result["navigation_attitude"].mean_squared =
        sum / result["navigation_attitude"].num_residual_blocks;
  }
  return result;
}

double Adjustment::SumSquaredReprojection() const {
  const std::vector<Image>& images = reconstruction_->Images();
  double sum = 0.0;
  for (size_t i = 0; i < images.size(); ++i) {
    const Camera& camera =
        reconstruction_->Cameras()[camera_index_.at(images[i].camera_id)];
    const double* params =
        camera_params_[camera_index_.at(images[i].camera_id)].data();
    const PoseBlock& pose = poses_[i];
    for (const Point2D& point2D : images[i].points2D) {
      if (!point2D.HasPoint3D()) continue;
      Eigen::Vector2d residual;
      VisitCameraModel(camera.model_id, [&](auto tag) {
        using Model = typename decltype(tag)::type;
        ReprojectionErrorCostFunctor<Model>(point2D.xy, 1.0)(
            pose.rotation, pose.translation,
            points_.at(point2D.point3D_id).data(), params, residual.data());
      });
      sum += residual.squaredNorm();
    }
  }
  return sum;
}

bool Adjustment::PlacementApplies() const {
  return !priors_.empty() && options_.weighting == NavWeighting::kLikelihood &&
         !options_.use_attitude && options_.nav_loss == LossType::kTrivial &&
         rig_pairings_.empty() && options_.refine_extrinsics;
}

std::vector<Eigen::Vector3d> Adjustment::PriorCentres() const {
  std::vector<Eigen::Vector3d> centres;
  for (const ImagePosePrior& prior : priors_) {
    const PoseBlock& pose = poses_[image_index_.at(prior.image_id)];
    const Eigen::Quaterniond cam_from_world(pose.rotation[0], pose.rotation[1],
                                            pose.rotation[2], pose.rotation[3]);
    centres.push_back(-(cam_from_world.conjugate() *
                        Eigen::Map<const Eigen::Vector3d>(pose.translation)));
  }
  return centres;
}

void Adjustment::SeedDiveOffsets() {
  if (!options_.dive_offsets || dive_offsets_.size() < 2) return;
  if (PlacementApplies()) {
    ReplaceOnPriors();
    return;
  }
  // Something else holds the placement (attitude priors, a rig): each
  // offset at its dive's information-weighted mean residual where the
  // model is.
  const std::vector<Eigen::Vector3d> centres = PriorCentres();
  std::map<int, Eigen::Matrix3d> information;
  std::map<int, Eigen::Vector3d> weighted;
  for (size_t i = 0; i < priors_.size(); ++i) {
    const int dive = priors_[i].dive;
    const Eigen::Matrix3d w = priors_[i].position_covariance.inverse();
    information.try_emplace(dive, Eigen::Matrix3d::Zero()).first->second += w;
    weighted.try_emplace(dive, Eigen::Vector3d::Zero()).first->second +=
        w * (centres[i] - priors_[i].position_in_world);
  }
  for (auto& [dive, offset] : dive_offsets_) {
    if (dive == reference_dive_) continue;
    offset = information.at(dive).ldlt().solve(weighted.at(dive));
  }
}

bool Adjustment::ReplaceOnPriors() {
  const std::vector<Eigen::Vector3d> centers = PriorCentres();
  // With dive offsets, the similarity and the offsets together: the model's
  // placement and the offsets trade off along a shallow valley, which
  // refitting the similarity alone to stale offsets does not cross.
  NavBundleAdjustmentOptions fit_options = options_;
  fit_options.reference_dive = reference_dive_;
  const SimilarityWithOffsets fit = FitToPriors(priors_, centers, fit_options);
  const Sim3d& new_from_old = fit.b_from_a;
  double offsets_move = 0.0;
  for (const auto& [dive, offset] : fit.offsets) {
    offsets_move =
        std::max(offsets_move, (offset - dive_offsets_.at(dive)).norm());
    dive_offsets_.at(dive) = offset;
  }
  double extent = 0.0;
  for (const Eigen::Vector3d& center : centers) {
    extent = std::max(extent, (center - centers.front()).norm());
  }
  constexpr double kNegligible = 1e-9;
  if (std::abs(new_from_old.scale - 1.0) < kNegligible &&
      Eigen::AngleAxisd(new_from_old.rotation).angle() < kNegligible &&
      new_from_old.translation.norm() < kNegligible * std::max(extent, 1.0) &&
      offsets_move < kNegligible * std::max(extent, 1.0)) {
    return false;
  }
  // x_cam = R_c x + t_c and x' = s R x + t give, with the camera frame
  // scaled by s too, R_c' = R_c R^T and t_c' = s t_c - R_c' t.
  const Eigen::Quaterniond rotation = new_from_old.rotation.normalized();
  for (PoseBlock& pose : poses_) {
    const Eigen::Quaterniond cam_from_old(pose.rotation[0], pose.rotation[1],
                                          pose.rotation[2], pose.rotation[3]);
    const Eigen::Quaterniond cam_from_new =
        (cam_from_old * rotation.conjugate()).normalized();
    Eigen::Map<Eigen::Vector3d> translation(pose.translation);
    translation = new_from_old.scale * translation -
                  cam_from_new * new_from_old.translation;
    pose.rotation[0] = cam_from_new.w();
    pose.rotation[1] = cam_from_new.x();
    pose.rotation[2] = cam_from_new.y();
    pose.rotation[3] = cam_from_new.z();
  }
  for (auto& [id, xyz] : points_) xyz = new_from_old * xyz;
  return true;
}

Adjustment::UndeterminedByImages Adjustment::FindUndeterminedByImages() const {
  const std::vector<Image>& images = reconstruction_->Images();
  std::vector<bool> image_out(images.size(), false);
  std::unordered_set<point3D_t> point_out;
  for (bool changed = true; changed;) {
    changed = false;
    std::vector<int> seen(images.size(), 0);
    for (const Point3D& point : reconstruction_->Points3D()) {
      if (point_out.count(point.point3D_id) != 0) continue;
      int observers = 0;
      for (const TrackElement& element : point.track) {
        observers += !image_out[image_index_.at(element.image_id)];
      }
      if (observers < 2) {
        point_out.insert(point.point3D_id);
        changed = true;
        continue;
      }
      for (const TrackElement& element : point.track) {
        ++seen[image_index_.at(element.image_id)];
      }
    }
    for (size_t i = 0; i < images.size(); ++i) {
      if (!image_out[i] && seen[i] < 3) {
        image_out[i] = true;
        changed = true;
      }
    }
  }
  UndeterminedByImages undetermined;
  for (size_t i = 0; i < images.size(); ++i) {
    if (image_out[i]) undetermined.images.push_back(i);
  }
  undetermined.points.assign(point_out.begin(), point_out.end());
  std::sort(undetermined.points.begin(), undetermined.points.end());
  return undetermined;
}

void Adjustment::EstimateOffsetCovariance(NavBundleAdjustmentReport* report) {
  const auto start = Clock::now();
  // Statistical weights: pixels by their sigma, the residuals' RMS per
  // degree of freedom (as ChoosePixelSigma), rig terms by their stated
  // sigmas, priors as the adjustment weighted them (likelihood weighting:
  // their sigmas x sigma_px / (lambda sigma_n), as
  // BundleCovarianceOptions::nav_weight_px_per_m). By their stated sigmas
  // they described another problem than the one solved: under --Nav.weight
  // auto with sigma_n 12x the stated (a seafloor survey whose dives the
  // images barely tie), an offset 1.3 m off was given +- 0.29 m. Until
  // 2026-12-07 the pixels were weighted by the RMS per coordinate, which
  // the fitted points and poses lower (0.445 px for 0.5 on the vent): the
  // offsets' sigmas came out 1.12-1.42x small on uwsim's worlds, |error| /
  // sigma RMS 1.48 over 63 coordinates.
  const long redundancy = ReprojectionRedundancy();
  if (redundancy <= 0) {
    report->covariance_note =
        "covariance not computed: the images have no redundancy to "
        "estimate their pixel noise";
    report->warnings.push_back(
        "the dive offsets have no uncertainty: the images have no "
        "redundancy to estimate their pixel noise");
    return;
  }
  const double rms_px = std::sqrt(SumSquaredReprojection() / redundancy);
  Weights weights;
  weights.reprojection = 1.0 / std::max(rms_px, 1e-6);
  weights.reprojection_loss_scale = options_.loss_scale_px / rms_px;
  const bool likelihood = options_.weighting == NavWeighting::kLikelihood;
  weights.nav = likelihood ? options_.weight_px_per_m * nav_sigma_m_ /
                                 std::max(rms_px, 1e-6)
                           : 1.0;
  weights.nav_loss_scale = options_.nav_loss_scale * weights.nav;
  // Rig terms as the adjustment weighted them too (pixel_sigma_ against
  // reprojections weighted 1).
  weights.rig = likelihood ? pixel_sigma_ / std::max(rms_px, 1e-6) : 1.0;
  ceres::Problem::Options problem_options;
  problem_options.manifold_ownership = ceres::TAKE_OWNERSHIP;
  problem_options.enable_fast_removal = true;
  ceres::Problem problem(problem_options);
  Build(weights, &problem, nullptr);
  const UndeterminedByImages undetermined = FindUndeterminedByImages();
  // Only blocks the problem holds: an image without observations, prior or
  // rig term was never added (Ceres aborts on removing a block it lacks).
  const auto remove = [&](double* block) {
    if (problem.HasParameterBlock(block)) problem.RemoveParameterBlock(block);
  };
  for (const size_t i : undetermined.images) {
    remove(poses_[i].rotation);
    remove(poses_[i].translation);
  }
  for (const point3D_t id : undetermined.points) remove(points_.at(id).data());
  const std::string left_out =
      undetermined.images.empty()
          ? std::string()
          : fmt::format(
                "; {} {} fewer than 3 points seen twice (e.g. {}) and {} "
                "points left with one image left out: the images do not fix "
                "their poses, so their priors tell nothing of the offsets",
                undetermined.images.size(),
                undetermined.images.size() == 1 ? "image that sees"
                                                : "images that see",
                reconstruction_->Images()[undetermined.images.front()].name,
                undetermined.points.size());

  ceres::Covariance::Options covariance_options;
  covariance_options.num_threads = NumThreads();
  ceres::Covariance covariance(covariance_options);
  std::vector<std::pair<const double*, const double*>> blocks;
  for (const auto& [dive, offset] : dive_offsets_) {
    if (dive != reference_dive_)
      blocks.emplace_back(offset.data(), offset.data());
  }
  if (!covariance.Compute(blocks, &problem)) {
    report->covariance_note =
        "covariance not computed: the problem is rank deficient (check that "
        "every dive overlaps another one)" +
        left_out;
    report->warnings.push_back(
        "the dive offsets have no uncertainty: their covariance is rank "
        "deficient" +
        left_out);
  } else {
    for (DiveOffsetEstimate& estimate : report->dive_offsets) {
      if (estimate.dive == reference_dive_) continue;
      Eigen::Matrix<double, 3, 3, Eigen::RowMajor> block;
      covariance.GetCovarianceBlock(dive_offsets_.at(estimate.dive).data(),
                                    dive_offsets_.at(estimate.dive).data(),
                                    block.data());
      estimate.covariance = block;
    }
    report->covariance_note =
        "Ceres covariance of the offsets with each residual weighted by its "
        "own sigma (pixel sigma " +
        std::to_string(rms_px) + " px, the reprojection residuals over " +
        std::to_string(redundancy) + " degrees of freedom; " +
        (likelihood ? "priors and rig terms as the adjustment weighted them: "
                      "the priors' stated sigmas x " +
                          std::to_string(1.0 / weights.nav)
                    : std::string("priors and rig terms by their stated "
                                  "sigmas (thesis weighting)")) +
        ")" + left_out;
  }
  report->covariance_time_s =
      std::chrono::duration<double>(Clock::now() - start).count();
}

void Adjustment::FillPriorResiduals(NavBundleAdjustmentReport* report) const {
  for (const ImagePosePrior& prior : priors_) {
    const PoseBlock& pose = poses_[image_index_.at(prior.image_id)];
    const int dive = options_.dive_offsets ? prior.dive : reference_dive_;
    PriorResidual residual;
    residual.image_id = prior.image_id;
    residual.dive = prior.dive;
    PositionPriorCostFunctor(prior.position_in_world,
                             Eigen::Matrix3d::Identity())(
        pose.rotation, pose.translation, dive_offsets_.at(dive).data(),
        residual.error_in_world.data());
    residual.mahalanobis =
        (SqrtInformation(prior.position_covariance) * residual.error_in_world)
            .norm();
    if (prior.cam_from_world_rotation) {
      Eigen::Vector3d rotation_vector;
      AttitudePriorCostFunctor(*prior.cam_from_world_rotation,
                               Eigen::Matrix3d::Identity())(
          pose.rotation, rotation_vector.data());
      residual.attitude_error_deg = rotation_vector.norm() * 180.0 / M_PI;
    }
    report->prior_residuals.push_back(residual);
  }
}

void Adjustment::CopyBack() const {
  std::vector<Image>& images = reconstruction_->Images();
  for (size_t i = 0; i < images.size(); ++i) {
    const PoseBlock& pose = poses_[i];
    images[i].cam_from_world.rotation = Eigen::Quaterniond(
        pose.rotation[0], pose.rotation[1], pose.rotation[2], pose.rotation[3]);
    images[i].cam_from_world.translation =
        Eigen::Map<const Eigen::Vector3d>(pose.translation);
  }
  for (size_t c = 0; c < camera_params_.size(); ++c) {
    reconstruction_->Cameras()[c].params = camera_params_[c];
  }
  // Each point's error: the mean reprojection error over its track, as
  // COLMAP stores it.
  for (Point3D& point : reconstruction_->Points3D()) {
    point.xyz = points_.at(point.point3D_id);
    if (point.track.empty()) continue;
    double sum = 0.0;
    for (const TrackElement& element : point.track) {
      const size_t i = image_index_.at(element.image_id);
      const Image& image = images[i];
      const size_t c = camera_index_.at(image.camera_id);
      Eigen::Vector2d residual;
      VisitCameraModel(reconstruction_->Cameras()[c].model_id, [&](auto tag) {
        using Model = typename decltype(tag)::type;
        ReprojectionErrorCostFunctor<Model>(
            image.points2D.at(element.point2D_idx).xy, 1.0)(
            poses_[i].rotation, poses_[i].translation, point.xyz.data(),
            camera_params_[c].data(), residual.data());
      });
      sum += residual.norm();
    }
    point.error = sum / point.track.size();
  }
  // COLMAP 4.x layout: a frame of a one-camera rig holds that camera's
  // pose.
  for (Frame& frame : reconstruction_->Frames()) {
    if (frame.data_ids.size() != 1) continue;
    const Image* image =
        reconstruction_->FindImage(static_cast<image_t>(frame.data_ids[0].id));
    if (image != nullptr) frame.rig_from_world = image->cam_from_world;
  }
}

NavBundleAdjustmentReport Adjustment::Run() {
  NavBundleAdjustmentReport report;
  report.gauge = ChooseGauge();
  report.num_images = static_cast<int>(poses_.size());
  report.num_points = static_cast<int>(points_.size());
  report.num_observations = static_cast<int>(num_observations_);
  report.nav_sigma_m = nav_sigma_m_;
  report.weight_px_per_m = priors_.empty() ? 0.0 : options_.weight_px_per_m;
  report.weighting = options_.weighting;

  // Reprojections (px) by 1; priors (in sigmas) by lambda sigma_n; rig
  // terms (in sigmas) by sigma_v. Eq. 2 further divides each objective by
  // its number of terms: reprojections by sqrt(M), priors by sqrt(N), rig
  // terms by sqrt(N_rig).
  const bool thesis = options_.weighting == NavWeighting::kThesis;
  const auto per_term = [thesis](size_t count) {
    return thesis ? 1.0 / std::sqrt(static_cast<double>(count)) : 1.0;
  };
  Weights weights;
  weights.reprojection = per_term(num_observations_);
  weights.reprojection_loss_scale =
      options_.loss_scale_px * weights.reprojection;
  if (!priors_.empty()) {
    weights.nav =
        options_.weight_px_per_m * nav_sigma_m_ * per_term(priors_.size());
    weights.nav_loss_scale = options_.nav_loss_scale * weights.nav;
  }
  if (!rig_pairings_.empty()) {
    if (priors_.empty()) {
      double sum = 0.0;
      for (const Point3D& point : reconstruction_->Points3D()) {
        if (point.HasError()) sum += point.error * point.error;
      }
      pixel_sigma_ =
          reconstruction_->Points3D().empty()
              ? 1.0
              : std::max(0.05,
                         std::sqrt(sum / reconstruction_->Points3D().size()));
    }
    weights.rig = pixel_sigma_ * per_term(rig_pairings_.size());
  }

  SeedDiveOffsets();
  ceres::Problem::Options problem_options;
  ceres::Problem problem(problem_options);
  std::map<std::string, std::vector<ceres::ResidualBlockId>> terms;
  Build(weights, &problem, &terms);
  report.initial_terms = EvaluateTerms(weights, &problem, terms);

  ceres::Solver::Options solver_options;
  // As COLMAP 3.8's BundleAdjuster: dense Schur up to 50 images, sparse
  // Schur up to 1000, iterative beyond.
  if (poses_.size() <= 50) {
    solver_options.linear_solver_type = ceres::DENSE_SCHUR;
  } else if (poses_.size() <= 1000) {
    solver_options.linear_solver_type = ceres::SPARSE_SCHUR;
  } else {
    solver_options.linear_solver_type = ceres::ITERATIVE_SCHUR;
    solver_options.preconditioner_type = ceres::SCHUR_JACOBI;
  }
  solver_options.max_num_iterations = options_.max_num_iterations;
  solver_options.max_linear_solver_iterations =
      options_.max_linear_solver_iterations;
  solver_options.function_tolerance = options_.function_tolerance;
  solver_options.gradient_tolerance = options_.gradient_tolerance;
  solver_options.parameter_tolerance = options_.parameter_tolerance;
  solver_options.max_num_consecutive_invalid_steps = 10;
  solver_options.max_consecutive_nonmonotonic_steps = 10;
  solver_options.num_threads = NumThreads();
  solver_options.use_nonmonotonic_steps = options_.use_nonmonotonic_steps;
  // Under the likelihood weighting the priors hold the model's placement
  // (a similarity: scale above all) only weakly against the images, and
  // Levenberg-Marquardt, stepping along tangents, crawls along that curved
  // valley (on a 33-image survey: 100 iterations, and the scale still 3 %
  // from where it settles). The valley's floor for the current shape is the
  // covariance-weighted similarity onto the priors, which leaves every
  // reprojection unchanged: placing the model there between solves gets
  // to the same minimum in a few rounds. Only with plain (non-robust)
  // position priors and nothing else that sees the placement (attitude
  // priors hold the rotation, rig baselines the scale).
  ceres::Solver::Summary summary;
  const auto start = Clock::now();
  constexpr int kMaxPlacementRounds = 5;
  const bool placement = PlacementApplies();
  const int round_iterations =
      std::max(10, options_.max_num_iterations / kMaxPlacementRounds);
  report.num_iterations = 0;
  for (int round = 1;; ++round) {
    const int remaining = options_.max_num_iterations - report.num_iterations;
    solver_options.max_num_iterations =
        placement && round < kMaxPlacementRounds
            ? std::min(remaining, round_iterations)
            : remaining;
    ceres::Solve(solver_options, &problem, &summary);
    if (summary.termination_type == ceres::FAILURE) {
      throw ErrorAt("bundle adjustment failed: ", summary.message);
    }
    report.num_iterations += static_cast<int>(summary.iterations.size()) - 1;
    if (!placement || round == kMaxPlacementRounds ||
        report.num_iterations >= options_.max_num_iterations) {
      break;
    }
    // Solve again after a move, or when the round ran out of iterations.
    if (!ReplaceOnPriors() &&
        summary.termination_type != ceres::NO_CONVERGENCE) {
      break;
    }
  }
  // 0 iterations asks for no solve: nothing to continue or fail.
  if (options_.unconverged == UnconvergedPolicy::kContinue &&
      options_.max_num_iterations > 0) {
    solver_options.max_num_iterations = options_.max_num_iterations;
    while (summary.termination_type == ceres::NO_CONVERGENCE &&
           report.num_continuations < options_.max_continuations) {
      ++report.num_continuations;
      if (placement) ReplaceOnPriors();
      ceres::Solve(solver_options, &problem, &summary);
      if (summary.termination_type == ceres::FAILURE) {
        throw ErrorAt("bundle adjustment failed: ", summary.message);
      }
      report.num_iterations += static_cast<int>(summary.iterations.size()) - 1;
    }
  }
  report.solve_time_s =
      std::chrono::duration<double>(Clock::now() - start).count();
  report.termination = ceres::TerminationTypeToString(summary.termination_type);
  if (summary.termination_type == ceres::NO_CONVERGENCE) {
    std::string reason =
        IterationLimitWarning(summary, options_.max_num_iterations);
    if (options_.unconverged == UnconvergedPolicy::kWarn ||
        options_.max_num_iterations == 0) {
      report.warnings.push_back(reason);
    } else {
      throw ErrorAt(
          "bundle adjustment did not converge",
          options_.unconverged == UnconvergedPolicy::kContinue
              ? fmt::format(" in {} iterations ({} solves of up to {})",
                            report.num_iterations, report.num_continuations + 1,
                            options_.max_num_iterations)
              : std::string(),
          ": ", reason,
          ". Nothing was written; --BundleAdjustment.unconverged warn keeps "
          "such a model, with this warning");
    }
  }
  report.solver = std::string(ceres::LinearSolverTypeToString(
                      summary.linear_solver_type_used)) +
                  ", " + std::to_string(summary.num_threads_used) + " threads";
  report.final_terms = EvaluateTerms(weights, &problem, terms);

  for (const auto& [dive, offset] : dive_offsets_) {
    DiveOffsetEstimate estimate;
    estimate.dive = dive;
    estimate.offset_in_world = offset;
    for (const ImagePosePrior& prior : priors_) {
      if (prior.dive == dive) ++estimate.num_images;
    }
    report.dive_offsets.push_back(estimate);
  }
  if (options_.dive_offsets && options_.estimate_offset_covariance &&
      dive_offsets_.size() > 1) {
    EstimateOffsetCovariance(&report);
  }
  FillPriorResiduals(&report);
  CopyBack();
  return report;
}

std::string Adjustment::ChooseCovarianceGauge(CovarianceGauge gauge) {
  const std::string twice =
      "the navigation priors fix the gauge; --Covariance.gauge " +
      CovarianceGaugeName(gauge) + " would fix it twice (use priors)";
  switch (gauge) {
    case CovarianceGauge::kPriors:
      if (priors_.empty()) {
        throw ErrorAt(
            "the gauge is not fixed: the model has no navigation priors; "
            "choose --Covariance.gauge held (the first image's pose and the "
            "second's scale, as COLMAP) or free_network (minimum trace)");
      }
      return ChooseGauge();
    case CovarianceGauge::kHeld:
      if (!priors_.empty()) throw ErrorAt(twice);
      return ChooseGauge();
    case CovarianceGauge::kFreeNetwork:
      if (!priors_.empty()) throw ErrorAt(twice);
      if (!rig_pairings_.empty()) {
        throw ErrorAt(
            "free_network with a rig: the rig's baselines fix the scale, so "
            "the gauge has 6 degrees of freedom; use --Covariance.gauge held");
      }
      if (!options_.refine_extrinsics) {
        throw ErrorAt(
            "free_network needs refined poses "
            "(--BundleAdjustment.refine_extrinsics 1)");
      }
      ChooseGauge();
      fixed_pose_.reset();
      fixed_translation_coordinate_.reset();
      return "free network: the minimum-norm pseudo-inverse (inner "
             "constraints on every pose and point)";
  }
  return "?";
}

long Adjustment::ReprojectionRedundancy() const {
  long parameters = 3 * static_cast<long>(points_.size());
  if (options_.refine_extrinsics)
    parameters += 6 * static_cast<long>(poses_.size());
  for (size_t c = 0; c < camera_params_.size(); ++c) {
    parameters +=
        static_cast<long>(camera_params_[c].size()) -
        static_cast<long>(ConstantCameraParams(
                              options_, reconstruction_->Cameras()[c].model_id)
                              .size());
  }
  if (options_.refine_extrinsics) parameters -= rig_pairings_.empty() ? 7 : 6;
  return 2 * static_cast<long>(num_observations_) - parameters;
}

void Adjustment::ChoosePixelSigma(const BundleCovarianceOptions& options,
                                  BundleCovariance* covariance) const {
  if (options.pixel_sigma_px > 0.0) {
    covariance->pixel_sigma_px = options.pixel_sigma_px;
    covariance->pixel_sigma_source = "given";
    return;
  }
  const long redundancy = ReprojectionRedundancy();
  if (redundancy <= 0) {
    throw ErrorAt("the images have no redundancy (", 2 * num_observations_,
                  " reprojection coordinates for ",
                  2 * static_cast<long>(num_observations_) - redundancy,
                  " parameters): the pixel noise cannot be estimated; give "
                  "--Covariance.pixel_sigma");
  }
  covariance->pixel_sigma_px = std::sqrt(SumSquaredReprojection() / redundancy);
  if (!(covariance->pixel_sigma_px > 0.0)) {
    throw ErrorAt(
        "the reprojection residuals are all zero: the pixel noise "
        "cannot be estimated; give --Covariance.pixel_sigma");
  }
  covariance->pixel_sigma_source = "estimated: sqrt(sum |r|^2 / redundancy " +
                                   std::to_string(redundancy) + ")";
}

void Adjustment::ChooseNavSigmaScale(const BundleCovarianceOptions& options,
                                     BundleCovariance* covariance) const {
  if (priors_.empty() || options.nav_weight_px_per_m == 0.0) {
    covariance->nav_sigma_source =
        priors_.empty() ? "no priors" : "the priors' sigmas as stated";
    return;
  }
  if (options_.weighting != NavWeighting::kLikelihood) {
    // Eq. 2 weights the priors M/N times their likelihood: no sigma of
    // theirs describes that.
    throw ErrorAt(
        "a navigation weight under --Nav.weighting ",
        NavWeightingName(options_.weighting),
        " is not a likelihood: give the covariance the priors as stated "
        "(--Covariance.nav_weight 0) or adjust with --Nav.weighting "
        "likelihood");
  }
  // The adjustment weighed a prior's error in sigmas by lambda sigma_n
  // against pixels, so as a likelihood with this pixel sigma its sigmas
  // were stated x sigma_px / (lambda sigma_n).
  covariance->nav_sigma_scale =
      covariance->pixel_sigma_px / (options.nav_weight_px_per_m * nav_sigma_m_);
  covariance->nav_sigma_source =
      fmt::format("as the adjustment weighted them: lambda {:g} px/m",
                  options.nav_weight_px_per_m);
}

void Adjustment::FillSimilarityNullSpace(
    const ceres::Problem& problem, const std::vector<point3D_t>& point_ids,
    SchurCovarianceOptions* options) const {
  // A similarity x' = (1 + sigma) x + omega x x + tau moves, to first order,
  // a point by [-[x]_x | I | x] (omega, tau, sigma), and a pose by
  // d = -R omega / 2, dt = -R tau + sigma t (Ceres' quaternion tangent d
  // rotates by the angle 2|d|: cam_from_world' = [cos|d|, sin|d| d/|d|] *
  // cam_from_world); intrinsics not at all.
  for (const PoseBlock& pose : poses_) {
    const Eigen::Matrix3d r =
        Eigen::Quaterniond(pose.rotation[0], pose.rotation[1], pose.rotation[2],
                           pose.rotation[3])
            .toRotationMatrix();
    Eigen::MatrixXd rows = Eigen::MatrixXd::Zero(6, 7);
    rows.block<3, 3>(0, 0) = -0.5 * r;
    rows.block<3, 3>(3, 3) = -r;
    rows.block<3, 1>(3, 6) =
        Eigen::Map<const Eigen::Vector3d>(pose.translation);
    options->null_space_reduced.push_back(rows);
  }
  for (const std::vector<double>& params : camera_params_) {
    if (!problem.HasParameterBlock(params.data())) continue;
    const int size = problem.IsParameterBlockConstant(params.data())
                         ? 0
                         : problem.ParameterBlockTangentSize(params.data());
    options->null_space_reduced.push_back(Eigen::MatrixXd::Zero(size, 7));
  }
  for (const point3D_t id : point_ids) {
    options->null_space_points.push_back(SimilarityTangentAt(points_.at(id)));
  }
}

CovarianceSamples Adjustment::ConvertSamples(
    const SchurCovariance& covariance,
    const std::vector<size_t>& camera_variables,
    const std::vector<Eigen::MatrixXd>& embeddings,
    const std::vector<point3D_t>& point_ids,
    const std::vector<CameraCovariance>& cameras) const {
  const Eigen::MatrixXd& tangent = covariance.samples;
  const int m = static_cast<int>(tangent.cols());
  const std::vector<Image>& images = reconstruction_->Images();
  CovarianceSamples samples;
  int camera_rows = 0;
  for (const CameraCovariance& camera : cameras) {
    samples.camera_ids.push_back(camera.camera_id);
    samples.camera_param_indices.push_back(camera.param_indices);
    camera_rows += static_cast<int>(camera.param_indices.size());
  }
  samples.camera_deltas.resize(camera_rows, m);
  int row = 0;
  for (size_t v = 0; v < camera_variables.size(); ++v) {
    // A SubsetManifold's tangent is the refined parameters in order.
    const int size = static_cast<int>(cameras[v].param_indices.size());
    samples.camera_deltas.middleRows(row, size) = tangent.middleRows(
        covariance.sample_row_of_reduced[images.size() + v], size);
    row += size;
  }
  samples.image_deltas.resize(6 * images.size(), m);
  for (size_t i = 0; i < images.size(); ++i) {
    samples.image_ids.push_back(images[i].image_id);
    samples.image_deltas.middleRows(6 * i, 6) =
        (embeddings[i] * tangent.middleRows(covariance.sample_row_of_reduced[i],
                                            embeddings[i].cols()))
            .cast<float>();
  }
  samples.point3D_ids = point_ids;
  samples.point_deltas =
      tangent.middleRows(covariance.sample_row_of_points, 3 * point_ids.size())
          .cast<float>();
  SeparateSimilarity(*reconstruction_, &samples);
  samples.Index();
  return samples;
}

BundleCovariance Adjustment::Covariance(
    const BundleCovarianceOptions& options) {
  const auto start = Clock::now();
  options.Check();
  BundleCovariance result;
  result.gauge = options.gauge;
  result.method = options.method;
  result.gauge_description = ChooseCovarianceGauge(options.gauge);
  result.num_observations = static_cast<int>(num_observations_);

  // What cannot have a covariance, named before anything is computed.
  const std::vector<Image>& images = reconstruction_->Images();
  std::vector<int> image_points(images.size(), 0);
  for (size_t i = 0; i < images.size(); ++i) {
    for (const Point2D& point2D : images[i].points2D) {
      if (point2D.HasPoint3D()) ++image_points[i];
    }
    if (options_.refine_extrinsics && image_points[i] < 3) {
      throw ErrorAt("image ", images[i].image_id, " (", images[i].name,
                    ") sees ", image_points[i],
                    " points: its pose needs at least 3 for a covariance");
    }
  }
  std::vector<point3D_t> point_ids;
  for (const Point3D& point : reconstruction_->Points3D()) {
    if (point.track.empty()) continue;
    if (!point.xyz.allFinite()) {
      throw ErrorAt("point ", point.point3D_id, " has a non-finite position");
    }
    if (point.track.size() < 2) {
      throw ErrorAt("point ", point.point3D_id, " is seen by ",
                    point.track.size(),
                    " image: its position has no covariance (filter tracks "
                    "shorter than 2)");
    }
    point_ids.push_back(point.point3D_id);
  }
  for (size_t c = 0; c < camera_params_.size(); ++c) {
    for (const double value : camera_params_[c]) {
      if (!std::isfinite(value)) {
        throw ErrorAt("camera ", reconstruction_->Cameras()[c].camera_id,
                      " has a non-finite parameter");
      }
    }
  }
  ChoosePixelSigma(options, &result);
  ChooseNavSigmaScale(options, &result);

  Weights weights;
  weights.reprojection = 1.0 / result.pixel_sigma_px;
  weights.reprojection_loss_scale =
      options_.loss_scale_px / result.pixel_sigma_px;
  weights.nav = 1.0 / result.nav_sigma_scale;
  weights.nav_loss_scale = options_.nav_loss_scale * weights.nav;
  // With priors the adjustment weighs the rig terms as it weighs them
  // (lambda sigma_n against pixels, Run()); without, by the pixel sigma.
  weights.rig = priors_.empty() ? 1.0 : weights.nav;
  ceres::Problem problem;
  Build(weights, &problem, nullptr);

  std::vector<ReducedVariable> reduced;
  for (size_t i = 0; i < images.size(); ++i) {
    reduced.push_back({{poses_[i].rotation, poses_[i].translation},
                       "image " + std::to_string(images[i].image_id) + " (" +
                           images[i].name + ")"});
  }
  std::vector<size_t> camera_variables;
  for (size_t c = 0; c < camera_params_.size(); ++c) {
    if (!problem.HasParameterBlock(camera_params_[c].data())) continue;
    camera_variables.push_back(c);
    reduced.push_back(
        {{camera_params_[c].data()},
         "camera " + std::to_string(reconstruction_->Cameras()[c].camera_id)});
  }
  std::vector<int> offset_variables;
  for (auto& [dive, offset] : dive_offsets_) {
    if (!problem.HasParameterBlock(offset.data())) continue;
    offset_variables.push_back(dive);
    reduced.push_back({{offset.data()},
                       "dive " + std::to_string(dive) + " navigation offset"});
  }
  std::vector<EliminatedPoint> points;
  for (const point3D_t id : point_ids) {
    points.push_back({points_.at(id).data(), "point " + std::to_string(id)});
  }
  SchurCovarianceOptions schur;
  schur.point_marginals = options.point_marginals;
  schur.covisible_cross = options.covisible_cross;
  schur.num_samples = options.num_samples;
  schur.sample_seed = options.sample_seed;
  schur.num_threads = NumThreads();
  if (options.gauge == CovarianceGauge::kFreeNetwork) {
    FillSimilarityNullSpace(problem, point_ids, &schur);
  }
  CeresCovarianceOptions ceres_options;
  ceres_options.num_threads = NumThreads();
  const SchurCovariance covariance =
      options.method == CovarianceMethod::kSchur
          ? ComputeSchurCovariance(&problem, reduced, points, schur)
          : ComputeCeresCovariance(&problem, reduced,
                                   options.point_marginals
                                       ? points
                                       : std::vector<EliminatedPoint>(),
                                   ceres_options);

  // Tangent coordinates of a pose -> [rotation (3); translation (3)].
  const auto pose_embedding = [&](size_t i) {
    const bool rotation_free =
        !problem.IsParameterBlockConstant(poses_[i].rotation);
    const bool translation_free =
        !problem.IsParameterBlockConstant(poses_[i].translation);
    std::vector<int> rows;
    if (rotation_free) rows.insert(rows.end(), {0, 1, 2});
    if (translation_free) {
      for (int k = 0; k < 3; ++k) {
        const bool fixed = fixed_translation_coordinate_ &&
                           fixed_translation_coordinate_->first == i &&
                           fixed_translation_coordinate_->second == k;
        if (!fixed) rows.push_back(3 + k);
      }
    }
    Eigen::MatrixXd embedding = Eigen::MatrixXd::Zero(6, rows.size());
    for (size_t x = 0; x < rows.size(); ++x) embedding(rows[x], x) = 1.0;
    // [d; dt] -> [w; c]: the rotation vector of Ceres' tangent is 2 d, so
    // w = -2 R^T d and c = -2 R^T [t]_x d - R^T dt.
    const Eigen::Matrix3d r =
        Eigen::Quaterniond(poses_[i].rotation[0], poses_[i].rotation[1],
                           poses_[i].rotation[2], poses_[i].rotation[3])
            .toRotationMatrix();
    const Eigen::Vector3d t =
        Eigen::Map<const Eigen::Vector3d>(poses_[i].translation);
    Eigen::Matrix3d t_cross;
    t_cross << 0.0, -t.z(), t.y(), t.z(), 0.0, -t.x(), -t.y(), t.x(), 0.0;
    Eigen::Matrix<double, 6, 6> to_world = Eigen::Matrix<double, 6, 6>::Zero();
    to_world.block<3, 3>(0, 0) = -2.0 * r.transpose();
    to_world.block<3, 3>(3, 0) = -2.0 * r.transpose() * t_cross;
    to_world.block<3, 3>(3, 3) = -r.transpose();
    return Eigen::MatrixXd(to_world * embedding);
  };
  std::vector<Eigen::MatrixXd> embeddings;
  for (size_t i = 0; i < images.size(); ++i) {
    embeddings.push_back(pose_embedding(i));
    ImageCovariance image;
    image.image_id = images[i].image_id;
    image.num_points = image_points[i];
    image.held = embeddings[i].cols() == 0;
    image.rotation_center =
        embeddings[i] * covariance.reduced[i] * embeddings[i].transpose();
    result.images.push_back(image);
  }
  for (size_t v = 0; v < camera_variables.size(); ++v) {
    const size_t c = camera_variables[v];
    CameraCovariance camera;
    camera.camera_id = reconstruction_->Cameras()[c].camera_id;
    const std::vector<int> constant =
        ConstantCameraParams(options_, reconstruction_->Cameras()[c].model_id);
    if (!problem.IsParameterBlockConstant(camera_params_[c].data())) {
      for (int k = 0; k < static_cast<int>(camera_params_[c].size()); ++k) {
        if (std::find(constant.begin(), constant.end(), k) == constant.end()) {
          camera.param_indices.push_back(k);
        }
      }
    }
    camera.params = covariance.reduced[images.size() + v];
    VisitCameraModel(reconstruction_->Cameras()[c].model_id, [&](auto tag) {
      using Model = typename decltype(tag)::type;
      for (const int index : Model::kFocalLengthIdxs) {
        const auto at = std::find(camera.param_indices.begin(),
                                  camera.param_indices.end(), index);
        if (at == camera.param_indices.end()) continue;
        const int k = static_cast<int>(at - camera.param_indices.begin());
        const double f = camera_params_[c][index];
        const double sigma = std::sqrt(camera.params(k, k));
        if (sigma > kPoorFocalLengthFraction * std::abs(f)) {
          result.warnings.push_back(
              "camera " + std::to_string(camera.camera_id) +
              ": focal length sigma " + std::to_string(sigma) + " px is " +
              std::to_string(100.0 * sigma / std::abs(f)) +
              " % of f: the self-calibration is nearly degenerate (the "
              "focal length trades against the distance to the scene), so "
              "the estimate may be off by several of these sigmas; fix the "
              "intrinsics from a calibration (uwcalib) or add relief and "
              "altitude changes");
        }
      }
    });
    result.cameras.push_back(camera);
  }
  for (size_t v = 0; v < offset_variables.size(); ++v) {
    const Eigen::MatrixXd& block =
        covariance.reduced[images.size() + camera_variables.size() + v];
    if (block.rows() == 3) result.dive_offsets[offset_variables[v]] = block;
  }
  for (size_t j = 0; j < covariance.points.size(); ++j) {
    PointCovariance point;
    point.point3D_id = point_ids[j];
    point.track_length = static_cast<int>(
        reconstruction_->FindPoint3D(point_ids[j])->track.size());
    point.xyz = covariance.points[j];
    result.points.push_back(point);
  }
  for (const auto& [pair, block] : covariance.cross) {
    const auto [a, b] = pair;
    if (a >= static_cast<int>(images.size()) ||
        b >= static_cast<int>(images.size())) {
      continue;
    }
    ImagePairCovariance cross;
    cross.image_id1 = images[a].image_id;
    cross.image_id2 = images[b].image_id;
    cross.rotation_center = embeddings[a] * block * embeddings[b].transpose();
    result.covisible.push_back(cross);
  }
  if (options.num_samples > 0) {
    result.samples = ConvertSamples(covariance, camera_variables, embeddings,
                                    point_ids, result.cameras);
  }
  result.num_residuals = covariance.num_residuals;
  result.num_reduced_coordinates = covariance.num_reduced_coordinates;
  result.factor_nonzeros = covariance.factor_nonzeros;
  result.reciprocal_condition = covariance.reciprocal_condition;
  result.jacobian_time_s = covariance.jacobian_time_s;
  result.schur_time_s = covariance.schur_time_s;
  result.factor_time_s = covariance.factor_time_s;
  result.inverse_time_s = covariance.inverse_time_s;
  result.total_time_s =
      std::chrono::duration<double>(Clock::now() - start).count();
  return result;
}
}  // namespace

NavBundleAdjustmentReport AdjustWithNavigation(
    const NavBundleAdjustmentOptions& options,
    const std::vector<ImagePosePrior>& priors, const SoftRig* rig,
    const std::unordered_map<image_t, double>& image_times,
    Reconstruction* reconstruction) {
  Adjustment adjustment(options, priors, rig, image_times, reconstruction);
  return adjustment.Run();
}

BundleCovariance EstimateBundleCovariance(
    const NavBundleAdjustmentOptions& adjuster,
    const std::vector<ImagePosePrior>& priors, const SoftRig* rig,
    const std::unordered_map<image_t, double>& image_times,
    const Reconstruction& model, const BundleCovarianceOptions& options) {
  Reconstruction copy = model;
  Adjustment adjustment(adjuster, priors, rig, image_times, &copy);
  BundleCovariance covariance = adjustment.Covariance(options);
  std::vector<Eigen::Vector2d> points;
  for (const PointCovariance& point : covariance.points) {
    points.push_back(model.FindPoint3D(point.point3D_id)->xyz.head<2>());
  }
  covariance.coverage_gaps = FindCoverageGaps(points, CoverageGapOptions());
  const CoverageGaps& gaps = covariance.coverage_gaps;
  if (!gaps.cell_centres.empty()) {
    covariance.warnings.push_back(fmt::format(
        "coverage gaps: {} cells of {:.2g} m ({:.3g} m^2) inside the survey "
        "hold no point; see uncertainty_map.png",
        gaps.cell_centres.size(), gaps.cell_size, gaps.Area()));
  }
  if (const auto warning =
          TrackLineWarning(model, priors, adjuster.use_attitude)) {
    covariance.warnings.push_back(*warning);
  }
  if (const auto warning = ScaleTransferWarning(model, !priors.empty())) {
    covariance.warnings.push_back(*warning);
  }
  if (!priors.empty()) {
    if (const auto warning = WeakRotationWarning(
            MedianRotationSigmaDeg(covariance), adjuster.use_attitude)) {
      covariance.warnings.push_back(*warning);
    }
  }
  covariance.short_baselines =
      FindShortBaselines(model, ShortBaselineOptions());
  const ShortBaselines& short_baselines = covariance.short_baselines;
  if (!short_baselines.cell_centres.empty()) {
    covariance.warnings.push_back(fmt::format(
        "short baselines: {} cells of {:.2g} m ({:.3g} m^2) whose points are "
        "seen over less than {:g} deg (median down to {:.2g} deg): every "
        "image there was taken from nearly one place, so depth is weak; see "
        "uncertainty_map.png",
        short_baselines.cell_centres.size(), short_baselines.cell_size,
        short_baselines.Area(), ShortBaselineOptions().min_angle_deg,
        *std::min_element(short_baselines.cell_median_angle_deg.begin(),
                          short_baselines.cell_median_angle_deg.end())));
  }
  return covariance;
}

}  // namespace uw
