#include "colmap_plugins/ba/track_line.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <Eigen/Eigenvalues>

#include "colmap_plugins/align/track_metrics.h"

namespace uw {

std::optional<std::string> TrackLineWarning(
    const Reconstruction& model, const std::vector<ImagePosePrior>& priors,
    bool attitude_priors) {
  if (attitude_priors) return std::nullopt;
  std::vector<Eigen::Vector3d> centres;
  for (const ImagePosePrior& prior : priors) {
    if (const Image* image = model.FindImage(prior.image_id)) {
      centres.push_back(image->ProjectionCenter());
    }
  }
  const std::optional<std::string> line = DescribeOneLineTrack(centres);
  if (!line) return std::nullopt;
  const bool log_has_attitude =
      std::any_of(priors.begin(), priors.end(), [](const ImagePosePrior& p) {
        return p.cam_from_world_rotation.has_value();
      });
  return "navigation positions on one pass: the " + *line +
         (log_has_attitude
              ? ". Fuse the log's roll and pitch too (--Nav.strategy prior "
                "--Nav.use_attitude 1)"
              : ". The log has no attitude to fix it with: a log with roll, "
                "pitch and heading would (--Nav.use_attitude 1)");
}

double MedianRotationSigmaDeg(const BundleCovariance& covariance) {
  std::vector<double> sigmas_deg;
  for (const ImageCovariance& image : covariance.images) {
    if (image.held) continue;
    const double largest = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(
                               image.RotationCovariance())
                               .eigenvalues()(2);
    sigmas_deg.push_back(std::sqrt(std::max(0.0, largest)) * 180.0 / M_PI);
  }
  if (sigmas_deg.empty()) return 0.0;
  std::nth_element(sigmas_deg.begin(),
                   sigmas_deg.begin() + sigmas_deg.size() / 2,
                   sigmas_deg.end());
  return sigmas_deg[sigmas_deg.size() / 2];
}

std::optional<std::string> WeakRotationWarning(double median_rotation_sigma_deg,
                                               bool attitude_priors) {
  if (attitude_priors ||
      !(median_rotation_sigma_deg > kMaxPriorRotationSigmaDeg)) {
    return std::nullopt;
  }
  return fmt::format(
      "the navigation positions fix the model's rotation only to {:.3g} deg "
      "(median camera, 1 sigma): a rotation this weak is not Gaussian, and "
      "the world-frame sigmas of poses and points can be 10-25 % too small "
      "(shape and scale are not affected). Add the log's attitude with "
      "--Nav.use_attitude 1",
      median_rotation_sigma_deg);
}

}  // namespace uw
