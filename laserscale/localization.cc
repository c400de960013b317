#include "laserscale/localization.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

#include <ceres/jet.h>
#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "colmap_plugins/cameras/camera_models.h"
#include "common/util/error.h"

namespace uw {
namespace {

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

// The reprojection residual of one match at (rotation, translation) and,
// when `jacobian` is given, its derivative by the left increment
// cam_from_world <- (exp(omega), delta) * cam_from_world, whose derivative
// of the point in the camera frame p is [-[p]x | I]. False if the point
// lies on or behind the camera plane.
template <typename Model>
bool MatchResidual(const double* params,
                   const ceres::Jet<double, 3>* jet_params,
                   const Correspondence2D3D& match,
                   const Eigen::Matrix3d& rotation,
                   const Eigen::Vector3d& translation,
                   Eigen::Vector2d* residual,
                   Eigen::Matrix<double, 2, 6>* jacobian) {
  using Jet = ceres::Jet<double, 3>;
  const Eigen::Vector3d p = rotation * match.point_in_world + translation;
  if (!(p.z() > 0.0)) return false;
  if (jacobian == nullptr) {
    Model::ImgFromCam(params, p.x(), p.y(), p.z(), &residual->x(),
                      &residual->y());
    *residual -= match.pixel;
    return true;
  }
  Jet x;
  Jet y;
  Model::ImgFromCam(jet_params, Jet(p.x(), 0), Jet(p.y(), 1), Jet(p.z(), 2), &x,
                    &y);
  *residual << x.a - match.pixel.x(), y.a - match.pixel.y();
  Eigen::Matrix<double, 3, 6> d_p_d_increment;
  d_p_d_increment << 0.0, p.z(), -p.y(), 1.0, 0.0, 0.0,  //
      -p.z(), 0.0, p.x(), 0.0, 1.0, 0.0,                 //
      p.y(), -p.x(), 0.0, 0.0, 0.0, 1.0;
  jacobian->row(0) = x.v.transpose() * d_p_d_increment;
  jacobian->row(1) = y.v.transpose() * d_p_d_increment;
  return true;
}

template <typename Model>
std::array<ceres::Jet<double, 3>, Model::kNumParams> JetParams(
    const double* params) {
  std::array<ceres::Jet<double, 3>, Model::kNumParams> jet_params;
  for (int i = 0; i < Model::kNumParams; ++i) {
    jet_params[i] = ceres::Jet<double, 3>(params[i]);
  }
  return jet_params;
}

const Correspondence2D3D& MatchAt(
    const std::vector<Correspondence2D3D>& matches,
    const std::vector<int>& indices, size_t k) {
  return matches[indices.empty() ? k : static_cast<size_t>(indices[k])];
}

// Sum of squared reprojection errors at (rotation, translation) and, when
// `jtj` is given, the Gauss-Newton normal equations of the left increment.
// False if a point lies on or behind the camera plane.
template <typename Model>
bool Accumulate(const double* params,
                const std::vector<Correspondence2D3D>& matches,
                const std::vector<int>& indices,
                const Eigen::Matrix3d& rotation,
                const Eigen::Vector3d& translation, double* cost, Matrix6d* jtj,
                Vector6d* jtr) {
  const auto jet_params = JetParams<Model>(params);
  *cost = 0.0;
  if (jtj != nullptr) {
    jtj->setZero();
    jtr->setZero();
  }
  Eigen::Vector2d residual;
  Eigen::Matrix<double, 2, 6> jacobian;
  const size_t n = indices.empty() ? matches.size() : indices.size();
  for (size_t k = 0; k < n; ++k) {
    if (!MatchResidual<Model>(
            params, jet_params.data(), MatchAt(matches, indices, k), rotation,
            translation, &residual, jtj == nullptr ? nullptr : &jacobian)) {
      return false;
    }
    *cost += residual.squaredNorm();
    if (jtj == nullptr) continue;
    jtj->noalias() += jacobian.transpose() * jacobian;
    jtr->noalias() += jacobian.transpose() * residual;
  }
  return true;
}

template <typename Model>
bool RefinePoseWithModel(const double* params,
                         const std::vector<Correspondence2D3D>& matches,
                         const std::vector<int>& indices, int max_iterations,
                         Rigid3d* cam_from_world) {
  Eigen::Matrix3d rotation = cam_from_world->RotationMatrix();
  Eigen::Vector3d translation = cam_from_world->translation;
  double cost = 0.0;
  Matrix6d jtj;
  Vector6d jtr;
  if (!Accumulate<Model>(params, matches, indices, rotation, translation, &cost,
                         &jtj, &jtr)) {
    return false;
  }
  double damping = 1e-6;
  for (int iteration = 0; iteration < max_iterations; ++iteration) {
    Matrix6d damped = jtj;
    damped.diagonal() += damping * jtj.diagonal().cwiseMax(1e-12);
    const Eigen::LDLT<Matrix6d> ldlt(damped);
    if (ldlt.info() != Eigen::Success) return false;
    const Vector6d step = -ldlt.solve(jtr);
    if (!step.allFinite()) return false;
    const Eigen::Vector3d omega = step.head<3>();
    const double angle = omega.norm();
    const Eigen::Matrix3d delta_rotation =
        angle > 0.0 ? Eigen::AngleAxisd(angle, omega / angle).toRotationMatrix()
                    : Eigen::Matrix3d::Identity().eval();
    const Eigen::Matrix3d new_rotation = delta_rotation * rotation;
    const Eigen::Vector3d new_translation =
        delta_rotation * translation + step.tail<3>();
    double new_cost = 0.0;
    const bool in_front =
        Accumulate<Model>(params, matches, indices, new_rotation,
                          new_translation, &new_cost, nullptr, nullptr);
    if (!in_front || new_cost > cost) {
      damping *= 10.0;
      if (damping > 1e8) break;
      continue;
    }
    const double decrease = cost - new_cost;
    rotation = new_rotation;
    translation = new_translation;
    cost = new_cost;
    damping = std::max(damping / 10.0, 1e-9);
    if (decrease <= 1e-12 * cost ||
        step.norm() <= 1e-12 * (1.0 + translation.norm())) {
      break;
    }
    Accumulate<Model>(params, matches, indices, rotation, translation, &cost,
                      &jtj, &jtr);
  }
  cam_from_world->rotation = Eigen::Quaterniond(rotation).normalized();
  cam_from_world->translation = translation;
  return true;
}

double MeanFocalLengthPx(const Camera& camera) {
  return CameraModelFocalLengths(camera.model_id, camera.params.data()).mean();
}

// Indices whose reprojection error through cam_from_world is below
// max_error_px and whose point is in front of the camera.
std::vector<int> InlierIndices(const Camera& camera,
                               const std::vector<Correspondence2D3D>& matches,
                               const Rigid3d& cam_from_world,
                               double max_error_px) {
  const Eigen::Matrix3d rotation = cam_from_world.RotationMatrix();
  std::vector<int> inliers;
  for (size_t i = 0; i < matches.size(); ++i) {
    const Eigen::Vector3d p =
        rotation * matches[i].point_in_world + cam_from_world.translation;
    if (!(p.z() > 0.0)) continue;
    if ((camera.ImgFromCam(p) - matches[i].pixel).norm() <= max_error_px) {
      inliers.push_back(static_cast<int>(i));
    }
  }
  return inliers;
}

}  // namespace

void LocalizationOptions::Check() const {
  if (!(max_error_px > 0.0) || !std::isfinite(max_error_px)) {
    throw ErrorAt("localization: max_error_px must be > 0, got ", max_error_px);
  }
  if (max_ransac_iterations < 1) {
    throw ErrorAt("localization: max_ransac_iterations must be >= 1");
  }
  if (!(ransac_confidence > 0.0 && ransac_confidence < 1.0)) {
    throw ErrorAt("localization: ransac_confidence must be in (0, 1), got ",
                  ransac_confidence);
  }
  if (min_num_inliers < 4) {
    throw ErrorAt("localization: min_num_inliers must be >= 4, got ",
                  min_num_inliers);
  }
  if (max_refine_iterations < 1) {
    throw ErrorAt("localization: max_refine_iterations must be >= 1");
  }
}

bool RefinePose(const Camera& camera,
                const std::vector<Correspondence2D3D>& matches,
                const std::vector<int>& indices, int max_iterations,
                Rigid3d* cam_from_world) {
  return VisitCameraModel(camera.model_id, [&](auto tag) {
    using Model = typename decltype(tag)::type;
    return RefinePoseWithModel<Model>(camera.params.data(), matches, indices,
                                      max_iterations, cam_from_world);
  });
}

LinearizedPose::LinearizedPose(const Camera& camera,
                               const std::vector<Correspondence2D3D>& matches,
                               const Rigid3d& cam_from_world)
    : nominal_(cam_from_world) {
  const Eigen::Matrix3d rotation = cam_from_world.RotationMatrix();
  Eigen::Matrix<double, Eigen::Dynamic, 6> jacobian(2 * matches.size(), 6);
  Eigen::VectorXd residuals(2 * matches.size());
  VisitCameraModel(camera.model_id, [&](auto tag) {
    using Model = typename decltype(tag)::type;
    const auto jet_params = JetParams<Model>(camera.params.data());
    Eigen::Vector2d residual;
    Eigen::Matrix<double, 2, 6> point_jacobian;
    for (size_t k = 0; k < matches.size(); ++k) {
      if (!MatchResidual<Model>(
              camera.params.data(), jet_params.data(), matches[k], rotation,
              cam_from_world.translation, &residual, &point_jacobian)) {
        throw ErrorAt("linearized pose: match ", k, " lies behind the camera");
      }
      jacobian.middleRows<2>(2 * k) = point_jacobian;
      residuals.segment<2>(2 * k) = residual;
    }
  });
  const Matrix6d normal = jacobian.transpose() * jacobian;
  const Eigen::LDLT<Matrix6d> ldlt(normal);
  if (ldlt.info() != Eigen::Success ||
      !(ldlt.vectorD().minCoeff() > 1e-12 * ldlt.vectorD().maxCoeff())) {
    throw ErrorAt("linearized pose: the matches do not constrain the pose");
  }
  gain_ = ldlt.solve(jacobian.transpose());
  step_at_nominal_ = -gain_ * residuals;
}

namespace {

// Left increment: rotation Exp(step.head(3)) applied to the pose, then the
// translation step.
Rigid3d StepPose(const Vector6d& step, const Rigid3d& pose) {
  const Eigen::Vector3d omega = step.head<3>();
  const double angle = omega.norm();
  const Eigen::Quaterniond delta_rotation =
      angle > 0.0 ? Eigen::Quaterniond(Eigen::AngleAxisd(angle, omega / angle))
                  : Eigen::Quaterniond::Identity();
  Rigid3d stepped;
  stepped.rotation = (delta_rotation * pose.rotation.normalized()).normalized();
  stepped.translation = delta_rotation * pose.translation + step.tail<3>();
  return stepped;
}

}  // namespace

Rigid3d LinearizedPose::Perturbed(const Eigen::VectorXd& pixel_offsets) const {
  return StepPose(step_at_nominal_ + gain_ * pixel_offsets, nominal_);
}

Rigid3d LinearizedPose::PerturbedFrom(
    const Rigid3d& refined, const Eigen::VectorXd& pixel_offsets) const {
  return StepPose(gain_ * pixel_offsets, refined);
}

double PoseRmsErrorPx(const Camera& camera,
                      const std::vector<Correspondence2D3D>& matches,
                      const std::vector<int>& indices,
                      const Rigid3d& cam_from_world) {
  const size_t n = indices.empty() ? matches.size() : indices.size();
  if (n <= 3) return 0.0;
  const Eigen::Matrix3d rotation = cam_from_world.RotationMatrix();
  double sum = 0.0;
  for (size_t k = 0; k < n; ++k) {
    const Correspondence2D3D& match =
        matches[indices.empty() ? k : static_cast<size_t>(indices[k])];
    const Eigen::Vector3d p =
        rotation * match.point_in_world + cam_from_world.translation;
    sum += (camera.ImgFromCam(p) - match.pixel).squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(2 * n - 6));
}

Localization LocalizeImage(const Camera& camera,
                           const std::vector<Correspondence2D3D>& matches,
                           const LocalizationOptions& options) {
  options.Check();
  Localization result;
  const auto fail = [&](const std::string& problem) {
    result.success = false;
    result.problem = problem;
    return result;
  };
  const size_t needed = static_cast<size_t>(options.min_num_inliers);
  if (matches.size() < needed) {
    std::ostringstream message;
    message << matches.size() << " 2D-3D correspondences, fewer than the "
            << options.min_num_inliers << " needed";
    return fail(message.str());
  }
  // PnP on undistorted rays through a virtual pinhole of the camera's focal
  // length (so that the threshold stays in pixels), so that every COLMAP
  // camera model is handled by its own unprojection.
  const double focal_px = MeanFocalLengthPx(camera);
  std::vector<cv::Point3d> object_points;
  std::vector<cv::Point2d> image_points;
  std::vector<int> kept;
  for (size_t i = 0; i < matches.size(); ++i) {
    const Correspondence2D3D& match = matches[i];
    if (!match.pixel.allFinite() || !match.point_in_world.allFinite()) continue;
    const Eigen::Vector3d ray = CameraModelCamFromImg(
        camera.model_id, camera.params.data(), match.pixel);
    if (!ray.allFinite()) continue;
    object_points.emplace_back(match.point_in_world.x(),
                               match.point_in_world.y(),
                               match.point_in_world.z());
    image_points.emplace_back(focal_px * ray.x(), focal_px * ray.y());
    kept.push_back(static_cast<int>(i));
  }
  if (kept.size() < needed) {
    return fail("too few finite correspondences the camera can unproject");
  }
  cv::UsacParams usac;
  usac.confidence = options.ransac_confidence;
  usac.maxIterations = options.max_ransac_iterations;
  usac.threshold = options.max_error_px;
  usac.randomGeneratorState = static_cast<int>(options.seed & 0x7fffffff);
  usac.score = cv::SCORE_METHOD_MAGSAC;
  usac.sampler = cv::SAMPLING_UNIFORM;
  usac.loMethod = cv::LOCAL_OPTIM_SIGMA;
  usac.isParallel = false;  // deterministic
  cv::Mat rvec;
  cv::Mat tvec;
  std::vector<int> usac_inliers;
  bool found = false;
  cv::Mat pinhole = cv::Mat::eye(3, 3, CV_64F);
  pinhole.at<double>(0, 0) = focal_px;
  pinhole.at<double>(1, 1) = focal_px;
  try {
    found = cv::solvePnPRansac(object_points, image_points, pinhole,
                               cv::noArray(), rvec, tvec, usac_inliers, usac);
  } catch (const cv::Exception& e) {
    return fail(std::string("PnP failed: ") + e.what());
  }
  if (!found || usac_inliers.size() < 4) return fail("PnP found no pose");
  cv::Mat rotation_cv;
  cv::Rodrigues(rvec, rotation_cv);
  Eigen::Matrix3d rotation;
  Eigen::Vector3d translation;
  cv::cv2eigen(rotation_cv, rotation);
  cv::cv2eigen(tvec, translation);
  Rigid3d cam_from_world;
  cam_from_world.rotation = Eigen::Quaterniond(rotation).normalized();
  cam_from_world.translation = translation;
  // Refine on the PnP's inliers, then re-select the inliers with the refined
  // pose and refine again until the set is stable.
  std::vector<int> inliers;
  for (const int i : usac_inliers) inliers.push_back(kept[i]);
  std::sort(inliers.begin(), inliers.end());
  for (int round = 0; round < 5; ++round) {
    if (!RefinePose(camera, matches, inliers, options.max_refine_iterations,
                    &cam_from_world)) {
      return fail("the pose refinement failed (points behind the camera)");
    }
    std::vector<int> refined =
        InlierIndices(camera, matches, cam_from_world, options.max_error_px);
    if (refined == inliers) break;
    inliers = std::move(refined);
    if (inliers.size() < needed) break;
  }
  if (inliers.size() < needed) {
    std::ostringstream message;
    message << inliers.size() << " inliers within " << options.max_error_px
            << " px, fewer than the " << options.min_num_inliers << " needed";
    return fail(message.str());
  }
  result.success = true;
  result.cam_from_world = cam_from_world;
  result.rms_error_px =
      PoseRmsErrorPx(camera, matches, inliers, cam_from_world);
  result.inliers = std::move(inliers);
  return result;
}

}  // namespace uw
