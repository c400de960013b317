#include "colmap_plugins/scene/camera_up.h"

#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

namespace uw {
namespace {

// The up a set of directions that should point down gives, when they agree
// (their mean is longer than `agreement`).
std::optional<Eigen::Vector3d> MinusMean(const Eigen::Vector3d& mean) {
  constexpr double kAgreement = 0.5;
  if (mean.norm() > kAgreement) return -mean.normalized();
  return std::nullopt;
}

}  // namespace

std::optional<CameraUp> UpFromCameras(const Reconstruction& model) {
  // Columns of world_from_cam's rotation: the camera axes in the model.
  std::vector<Eigen::Matrix3d> model_from_cams;
  for (const Image& image : model.Images()) {
    model_from_cams.push_back(
        image.cam_from_world.rotation.toRotationMatrix().transpose());
  }
  if (model_from_cams.empty()) return std::nullopt;
  Eigen::Vector3d optical_axis = Eigen::Vector3d::Zero();
  Eigen::Vector3d image_down = Eigen::Vector3d::Zero();
  // A vehicle turns about the vertical (its heading) and little about
  // anything else: the turns between the cameras share that axis.
  Eigen::Matrix3d turns = Eigen::Matrix3d::Zero();
  double largest_turn = 0.0;
  for (const Eigen::Matrix3d& model_from_cam : model_from_cams) {
    optical_axis += model_from_cam.col(2);
    image_down += model_from_cam.col(1);
    const Eigen::AngleAxisd turn(model_from_cam *
                                 model_from_cams.front().transpose());
    turns +=
        turn.angle() * turn.angle() * turn.axis() * turn.axis().transpose();
    largest_turn = std::max(largest_turn, turn.angle());
  }
  const double count = static_cast<double>(model_from_cams.size());
  optical_axis /= count;
  image_down /= count;

  constexpr double kSignificantTurn = 0.35;  // 20 deg
  constexpr double kSharedAxis = 0.8;
  if (largest_turn > kSignificantTurn) {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(turns);
    const double share = solver.eigenvalues()(2) / turns.trace();
    Eigen::Vector3d axis = solver.eigenvectors().col(2);
    // Cameras look down at a floor or hold their images upright at a
    // wall: either way their axes point down on the whole.
    const double down = (optical_axis + image_down).dot(axis);
    if (share > kSharedAxis && std::abs(down) > 0.5) {
      if (down > 0.0) axis = -axis;
      return CameraUp{axis, "the axis the cameras turn about", share};
    }
    return std::nullopt;
  }
  // No turn to tell a floor from a wall (at a wall the images' down
  // agrees as the optical axes do): assume the usual floor survey, and say
  // so.
  if (const auto up = MinusMean(optical_axis)) {
    return CameraUp{*up,
                    "assumed: the cameras look down (they do not turn, so a "
                    "floor cannot be told from a wall)",
                    optical_axis.norm()};
  }
  if (const auto up = MinusMean(image_down)) {
    return CameraUp{*up, "the images' up (they do not turn)",
                    image_down.norm()};
  }
  return std::nullopt;
}

Eigen::Matrix3d ViewFromModel(const Eigen::Vector3d& up_in_model) {
  const Eigen::Vector3d z = up_in_model.normalized();
  const Eigen::Vector3d reference = std::abs(z.x()) < 0.9
                                        ? Eigen::Vector3d::UnitX()
                                        : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d x = (reference - reference.dot(z) * z).normalized();
  Eigen::Matrix3d view_from_model;
  view_from_model.row(0) = x.transpose();
  view_from_model.row(1) = z.cross(x).transpose();
  view_from_model.row(2) = z.transpose();
  return view_from_model;
}

}  // namespace uw
