#include "calib/projection_uncertainty.h"

#include <cmath>
#include <limits>

extern "C" {
// mrcal's headers have no extern "C" of their own.
#include <mrcal/mrcal.h>
#include <mrcal/poseutils.h>
}

#include "common/util/error.h"

namespace uw {
namespace {

using RowMatrix36 = Eigen::Matrix<double, 3, 6, Eigen::RowMajor>;
using RowMatrix33 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;

mrcal_lensmodel_t LensModel(const std::string& name) {
  mrcal_lensmodel_t model;
  if (!mrcal_lensmodel_from_name(&model, name.c_str()) ||
      !mrcal_lensmodel_type_is_valid(model.type)) {
    throw ErrorAt("projection uncertainty: lens model '", name,
                  "' is not one of mrcal's");
  }
  return model;
}

// y = T x for mrcal's rt (or T⁻¹ x if inverted), with dy/drt and dy/dx of
// the forward transform.
Eigen::Vector3d Transform(const Eigen::Matrix<double, 6, 1>& rt,
                          const Eigen::Vector3d& x, bool inverted,
                          RowMatrix36* dy_drt = nullptr,
                          RowMatrix33* dy_dx = nullptr) {
  Eigen::Vector3d y;
  mrcal_transform_point_rt_full(y.data(), 0, dy_drt ? dy_drt->data() : nullptr,
                                0, 0, dy_dx ? dy_dx->data() : nullptr, 0, 0,
                                rt.data(), 0, x.data(), 0, inverted);
  return y;
}

// y = R x for the Rodrigues vector r (or Rᵀ x), with dy/dr and dy/dx.
Eigen::Vector3d Rotate(const Eigen::Vector3d& r, const Eigen::Vector3d& x,
                       bool inverted, RowMatrix33* dy_dr = nullptr,
                       RowMatrix33* dy_dx = nullptr) {
  Eigen::Vector3d y;
  mrcal_rotate_point_r_full(y.data(), 0, dy_dr ? dy_dr->data() : nullptr, 0, 0,
                            dy_dx ? dy_dx->data() : nullptr, 0, 0, r.data(), 0,
                            x.data(), 0, inverted);
  return y;
}

}  // namespace

Eigen::Matrix2d ProjectionCovariance(const MrcalCalibration& camera,
                                     const Eigen::Vector3d& point_in_cam,
                                     bool at_infinity) {
  const MrcalSolveCovariance& solve = camera.covariance;
  const mrcal_lensmodel_t model = LensModel(camera.lens_model);
  const int num_intrinsics = mrcal_lensmodel_num_params(&model);
  const int num_frames = static_cast<int>(solve.rt_ref_from_frame.size());
  const int first_frame = num_intrinsics + (solve.has_rt_cam_from_ref ? 6 : 0);
  const int num_states = first_frame + 6 * num_frames;
  if (static_cast<int>(camera.intrinsics.size()) != num_intrinsics ||
      num_frames == 0 || solve.state.rows() != num_states ||
      solve.state.cols() != num_states) {
    throw Error(
        "projection uncertainty: the calibration carries no covariance of its "
        "solve (CalibrateRigWithMrcal's)");
  }

  // G = dq/db over (intrinsics, camera pose, board poses).
  Eigen::MatrixXd dq_db = Eigen::MatrixXd::Zero(2, num_states);
  mrcal_point2_t q;
  mrcal_point3_t dq_dp[2];
  Eigen::Matrix<double, 2, Eigen::Dynamic, Eigen::RowMajor> dq_dintrinsics(
      2, num_intrinsics);
  const mrcal_point3_t p{
      {point_in_cam.x(), point_in_cam.y(), point_in_cam.z()}};
  if (!mrcal_project(&q, dq_dp, dq_dintrinsics.data(), &p, 1, &model,
                     camera.intrinsics.data())) {
    throw ErrorAt("projection uncertainty: mrcal cannot project with ",
                  camera.lens_model, "'s gradients");
  }
  dq_db.leftCols(num_intrinsics) = dq_dintrinsics;
  Eigen::Matrix<double, 2, 3> dq_dpoint;
  dq_dpoint << dq_dp[0].x, dq_dp[0].y, dq_dp[0].z, dq_dp[1].x, dq_dp[1].y,
      dq_dp[1].z;

  // The point in the rig's frame, and how q moves with it (through the
  // camera's pose) and with the pose itself.
  Eigen::Vector3d in_ref = point_in_cam;
  Eigen::Matrix<double, 2, 3> dq_dref = dq_dpoint;
  if (solve.has_rt_cam_from_ref) {
    RowMatrix33 dcam_dref;
    if (at_infinity) {
      const Eigen::Vector3d r = solve.rt_cam_from_ref.head<3>();
      in_ref = Rotate(r, point_in_cam, true);
      RowMatrix33 dcam_dr;
      Rotate(r, in_ref, false, &dcam_dr, &dcam_dref);
      dq_db.block<2, 3>(0, num_intrinsics) = dq_dpoint * dcam_dr;
    } else {
      in_ref = Transform(solve.rt_cam_from_ref, point_in_cam, true);
      RowMatrix36 dcam_drt;
      Transform(solve.rt_cam_from_ref, in_ref, false, &dcam_drt, &dcam_dref);
      dq_db.block<2, 6>(0, num_intrinsics) = dq_dpoint * dcam_drt;
    }
    dq_dref = dq_dpoint * dcam_dref;
  }
  // Mean-frames: the point in each board's frame, back to the rig's frame
  // through that board's (perturbed) pose, averaged.
  for (int f = 0; f < num_frames; ++f) {
    const Eigen::Matrix<double, 6, 1>& rt = solve.rt_ref_from_frame[f];
    const int column = first_frame + 6 * f;
    if (at_infinity) {
      const Eigen::Vector3d r = rt.head<3>();
      RowMatrix33 dref_dr;
      Rotate(r, Rotate(r, in_ref, true), false, &dref_dr);
      dq_db.block<2, 3>(0, column) = dq_dref * dref_dr / num_frames;
    } else {
      RowMatrix36 dref_drt;
      Transform(rt, Transform(rt, in_ref, true), false, &dref_drt);
      dq_db.block<2, 6>(0, column) = dq_dref * dref_drt / num_frames;
    }
  }
  const double variance =
      solve.observed_pixel_sigma * solve.observed_pixel_sigma;
  return variance * dq_db * solve.state * dq_db.transpose();
}

double WorstDirectionStdev(const Eigen::Matrix2d& covariance) {
  const double a = covariance(0, 0);
  const double b = covariance(1, 0);
  const double c = covariance(1, 1);
  return std::sqrt((a + c) / 2.0 + std::sqrt((a - c) * (a - c) / 4.0 + b * b));
}

double ProjectionUncertaintyAtPixel(const MrcalCalibration& camera,
                                    const Eigen::Vector2d& pixel,
                                    double distance) {
  const mrcal_lensmodel_t model = LensModel(camera.lens_model);
  const mrcal_point2_t q{{pixel.x(), pixel.y()}};
  mrcal_point3_t v;
  const Eigen::Map<const Eigen::Vector3d> ray(v.xyz);
  if (!mrcal_unproject(&v, &q, 1, &model, camera.intrinsics.data()) ||
      !ray.allFinite() || !(ray.norm() > 0.0)) {
    return std::numeric_limits<double>::infinity();
  }
  const bool at_infinity = distance == 0.0;
  const Eigen::Vector3d point =
      ray.normalized() * (at_infinity ? 1.0 : distance);
  const double stdev =
      WorstDirectionStdev(ProjectionCovariance(camera, point, at_infinity));
  return std::isfinite(stdev) ? stdev : std::numeric_limits<double>::infinity();
}

void ProjectionUncertaintyOptions::Check() const {
  if (!(distance >= 0.0) || !std::isfinite(distance)) {
    throw Error(
        "projection uncertainty: distance must be >= 0 (0 is infinity)");
  }
  if (grid_width < 2 || grid_height < 2) {
    throw Error(
        "projection uncertainty: grid_width and grid_height must be >= 2");
  }
}

double ProjectionUncertaintyMap::MaxPx() const {
  return stdev_px.size() == 0 ? 0.0 : stdev_px.maxCoeff();
}

ProjectionUncertaintyMap MapProjectionUncertainty(
    const MrcalCalibration& camera,
    const ProjectionUncertaintyOptions& options) {
  options.Check();
  ProjectionUncertaintyMap map;
  map.distance = options.distance;
  map.observed_pixel_sigma = camera.covariance.observed_pixel_sigma;
  // mrcal's sample_imager: evenly from the first pixel to the last.
  const auto samples = [](int count, int size) {
    std::vector<double> values(count);
    for (int i = 0; i < count; ++i) {
      values[i] = static_cast<double>(i) * (size - 1) / (count - 1);
    }
    return values;
  };
  map.x_px = samples(options.grid_width, camera.image_width);
  map.y_px = samples(options.grid_height, camera.image_height);
  map.stdev_px.resize(options.grid_height, options.grid_width);
  for (int i = 0; i < options.grid_height; ++i) {
    for (int j = 0; j < options.grid_width; ++j) {
      map.stdev_px(i, j) = ProjectionUncertaintyAtPixel(
          camera, {map.x_px[j], map.y_px[i]}, options.distance);
    }
  }
  map.at_centre_px = ProjectionUncertaintyAtPixel(
      camera, {(camera.image_width - 1) / 2.0, (camera.image_height - 1) / 2.0},
      options.distance);
  return map;
}

}  // namespace uw
