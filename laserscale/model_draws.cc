#include "laserscale/model_draws.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "colmap_plugins/ba/covariance_files.h"
#include "common/util/error.h"

namespace uw {

ModelDraws ReadModelDraws(const std::filesystem::path& dir,
                          const Reconstruction& model) {
  const std::filesystem::path samples_path = dir / "samples.bin";
  if (!std::filesystem::exists(samples_path)) {
    throw ErrorAt(samples_path.string(),
                  ": missing; run uwcolmap covariance_estimator with "
                  "--Covariance.samples 200 (or more)");
  }
  // The sidecar checks every image and point against the model, so that
  // draws of the same model adjusted since are refused too (samples.bin
  // alone only knows the model's structure); it also holds the gauge.
  const BundleCovariance covariance =
      ReadCovarianceSidecar(dir / "covariance.bin", model);
  ModelDraws draws;
  draws.gauge = CovarianceGaugeName(covariance.gauge);
  draws.samples = ReadCovarianceSamples(samples_path, model);
  const int n = draws.samples.NumSamples();
  if (n < 2) {
    throw ErrorAt(samples_path.string(), ": ", n,
                  " draw(s); at least 2 are needed");
  }
  const Eigen::VectorXd& log_scale = draws.samples.log_scale;
  draws.log_scale_sigma = std::sqrt(
      (log_scale.array() - log_scale.mean()).square().sum() / (n - 1.0));
  return draws;
}

ImageModelDraws DrawsForImage(const ModelDraws& draws,
                              const Reconstruction& model,
                              const LocalizedImage& pose,
                              const Eigen::Vector3d& surface_at,
                              int num_surface_points) {
  const CovarianceSamples& samples = draws.samples;
  const int num_draws = samples.NumSamples();
  const std::string named = "laser image " + pose.name;
  ImageModelDraws result;
  std::vector<std::string> notes;

  // The camera: the model's, refined or held in the adjustment.
  const Camera* camera = model.FindCamera(pose.camera.camera_id);
  if (camera != nullptr) {
    if (camera->model_id != pose.camera.model_id ||
        camera->params != pose.camera.params) {
      throw ErrorAt(named, ": camera ", pose.camera.camera_id,
                    " differs from the model's (localized against another "
                    "model?)");
    }
    const auto found = std::find(samples.camera_ids.begin(),
                                 samples.camera_ids.end(), camera->camera_id);
    const int row = samples.CameraRow(camera->camera_id);
    if (found != samples.camera_ids.end() && row >= 0) {
      result.param_indices =
          samples.camera_param_indices[found - samples.camera_ids.begin()];
      result.camera_deltas = samples.camera_deltas.middleRows(
          row, static_cast<Eigen::Index>(result.param_indices.size()));
    } else {
      notes.push_back("the model's intrinsics were held: not sampled");
    }
  } else {
    notes.push_back("camera " + std::to_string(pose.camera.camera_id) +
                    " is not the model's: its intrinsics are not sampled");
  }

  // The points of the localization.
  result.point_deltas.setZero(
      3 * static_cast<Eigen::Index>(pose.inliers.size()), num_draws);
  for (size_t k = 0; k < pose.inliers.size(); ++k) {
    const Correspondence2D3D& match = pose.inliers[k];
    if (match.point3D_id == kInvalidPoint3DId) {
      throw ErrorAt(named, ": inlier ", k,
                    " has no point3D_id (poses.json of version 1?); "
                    "localize it again to sample the model");
    }
    const Point3D* point = model.FindPoint3D(match.point3D_id);
    if (point == nullptr || (point->xyz - match.point_in_world).norm() >
                                1e-9 * (1.0 + point->xyz.norm())) {
      throw ErrorAt(named, ": inlier ", k, " (point3D ", match.point3D_id,
                    ") is not where the model has it: localized against "
                    "another model?");
    }
    const int row = samples.PointRow(match.point3D_id);
    if (row < 0) {
      ++result.num_points_without_draws;
      continue;
    }
    result.point_deltas.middleRows<3>(3 * static_cast<Eigen::Index>(k)) =
        samples.point_deltas.middleRows<3>(row);
  }

  // The surface under the hits moves as the model's points nearest them.
  std::vector<std::pair<double, int>> nearest;
  nearest.reserve(samples.point3D_ids.size());
  for (const point3D_t id : samples.point3D_ids) {
    const Point3D* point = model.FindPoint3D(id);
    if (point == nullptr) continue;
    nearest.emplace_back((point->xyz - surface_at).squaredNorm(),
                         samples.PointRow(id));
  }
  if (nearest.empty()) {
    throw ErrorAt(named, ": the draws hold no point of the model");
  }
  const size_t k = std::min(
      nearest.size(), static_cast<size_t>(std::max(1, num_surface_points)));
  std::partial_sort(nearest.begin(), nearest.begin() + k, nearest.end());
  result.surface_shifts.setZero(3, num_draws);
  for (size_t i = 0; i < k; ++i) {
    result.surface_shifts +=
        samples.point_deltas.middleRows<3>(nearest[i].second);
  }
  result.surface_shifts /= static_cast<float>(k);
  result.surface_radius = std::sqrt(nearest[k - 1].first);
  if (result.num_points_without_draws > 0) {
    notes.push_back(std::to_string(result.num_points_without_draws) + " of " +
                    std::to_string(pose.inliers.size()) +
                    " inlier points have no draws (taken as exact)");
  }
  for (const std::string& note : notes) {
    result.note += (result.note.empty() ? "" : "; ") + note;
  }
  return result;
}

}  // namespace uw
