#include "colmap_plugins/ba/track_line.h"

#include <cmath>

#include <fmt/format.h>
#include <Eigen/Eigenvalues>

namespace uw {

TrackSpread MeasureTrackSpread(const std::vector<Eigen::Vector3d>& centres) {
  TrackSpread spread;
  if (centres.empty()) return spread;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& centre : centres) mean += centre;
  mean /= static_cast<double>(centres.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& centre : centres) {
    scatter += (centre - mean) * (centre - mean).transpose();
  }
  scatter /= static_cast<double>(centres.size());
  // Ascending eigenvalues.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter);
  spread.along_m = std::sqrt(std::max(0.0, solver.eigenvalues()(2)));
  spread.across_m = std::sqrt(std::max(0.0, solver.eigenvalues()(1)));
  spread.axis = solver.eigenvectors().col(2);
  return spread;
}

std::optional<std::string> TrackLineWarning(
    const Reconstruction& model, const std::vector<ImagePosePrior>& priors,
    bool attitude_priors) {
  if (priors.size() < 3 || attitude_priors) return std::nullopt;
  std::vector<Eigen::Vector3d> centres;
  for (const ImagePosePrior& prior : priors) {
    if (const Image* image = model.FindImage(prior.image_id)) {
      centres.push_back(image->ProjectionCenter());
    }
  }
  const TrackSpread spread = MeasureTrackSpread(centres);
  if (!(spread.across_m < kMinAcrossAlongSpread * spread.along_m)) {
    return std::nullopt;
  }
  return fmt::format(
      "the {} images with navigation positions lie nearly on one line (RMS "
      "{:.3g} m "
      "across it, {:.3g} m along, axis [{:.2f}, {:.2f}, {:.2f}]): without "
      "attitude priors only that scatter fixes the model's rotation about "
      "the line, so that rotation (and the world position of everything "
      "off the line) can be several of its stated sigmas off; shape and "
      "scale are not affected. Add the log's roll and pitch with "
      "--Nav.use_attitude 1",
      centres.size(), spread.across_m, spread.along_m, spread.axis.x(),
      spread.axis.y(), spread.axis.z());
}

}  // namespace uw
