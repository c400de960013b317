#include "calib/mrcal_calibration.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <suitesparse/cholmod.h>
#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>
#include <opencv2/calib3d.hpp>

extern "C" {
// mrcal's headers have no extern "C" of their own.
#include <mrcal/mrcal.h>
// After mrcal.h, which it needs: the Jacobian's size
// (_mrcal_num_j_nonzero), exported for mrcal's Python wrapper only.
#include <mrcal/mrcal-internal.h>
}

#include "common/util/error.h"
#include "common/util/file.h"

namespace uw {
namespace {

mrcal_lensmodel_t LensModel(const std::string& name) {
  mrcal_lensmodel_t model;
  if (!mrcal_lensmodel_from_name(&model, name.c_str()) ||
      !mrcal_lensmodel_type_is_valid(model.type)) {
    throw ErrorAt("lens model '", name,
                  "' is not one of mrcal's (e.g. LENSMODEL_OPENCV4, "
                  "LENSMODEL_OPENCV8, LENSMODEL_SPLINED_STEREOGRAPHIC_order=3_"
                  "Nx=16_Ny=12_fov_x_deg=100)");
  }
  return model;
}

Eigen::Matrix3d RotationFromRodrigues(const mrcal_point3_t& r) {
  const Eigen::Vector3d axis(r.x, r.y, r.z);
  const double angle = axis.norm();
  if (angle < 1e-300) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, axis / angle).toRotationMatrix();
}

mrcal_pose_t PoseFromRigid(const Rigid3d& b_from_a) {
  const Eigen::AngleAxisd rotation(b_from_a.rotation.normalized());
  const Eigen::Vector3d r = rotation.angle() * rotation.axis();
  mrcal_pose_t pose;
  for (int i = 0; i < 3; ++i) {
    pose.r.xyz[i] = r(i);
    pose.t.xyz[i] = b_from_a.translation(i);
  }
  return pose;
}

Rigid3d RigidFromPose(const mrcal_pose_t& pose) {
  Rigid3d rigid;
  rigid.rotation = Eigen::Quaterniond(RotationFromRodrigues(pose.r));
  rigid.translation = Eigen::Vector3d(pose.t.x, pose.t.y, pose.t.z);
  return rigid;
}

Rigid3d Compose(const Rigid3d& c_from_b, const Rigid3d& b_from_a) {
  Rigid3d c_from_a;
  c_from_a.rotation =
      c_from_b.rotation.normalized() * b_from_a.rotation.normalized();
  c_from_a.translation = c_from_b * b_from_a.translation;
  return c_from_a;
}

// One board view of one camera, as mrcal takes it.
struct View {
  int camera = 0;
  int frame = 0;           // index into frames_toref
  size_t source = 0;       // index into the camera's views
  Rigid3d cam_from_board;  // the seed
};

// The problem mrcal_optimize() solves, stage by stage, in place.
struct Problem {
  int num_cameras = 1;
  std::vector<double> intrinsics;                // num_cameras x num_params
  std::vector<mrcal_pose_t> extrinsics_fromref;  // cameras 1.. from camera 0
  std::vector<mrcal_pose_t> frames_toref;        // ref (camera 0) from board
  std::vector<mrcal_observation_board_t> observations;  // sorted by frame
  std::vector<mrcal_point3_t> pool;  // (Nobs, H, W): x, y, weight
  std::vector<bool> found;           // per pool entry: found by the detector
  mrcal_calobject_warp_t warp{};
  std::vector<int> imagersizes;
  mrcal_problem_selections_t selections{};  // the last Solve's
  const mrcal_problem_constants_t constants{-1.0, -1.0};

  mrcal_stats_t Solve(const mrcal_lensmodel_t& model, bool core,
                      bool distortions, bool regularization, bool outliers,
                      bool warp_too, const CalibrationBoard& board) {
    selections = {};
    selections.do_optimize_intrinsics_core = core;
    selections.do_optimize_intrinsics_distortions = distortions;
    selections.do_optimize_extrinsics = true;
    selections.do_optimize_frames = true;
    selections.do_optimize_calobject_warp = warp_too;
    selections.do_apply_regularization = regularization;
    selections.do_apply_outlier_rejection = outliers;
    const mrcal_stats_t stats = mrcal_optimize(
        nullptr, 0, nullptr, 0, intrinsics.data(), extrinsics_fromref.data(),
        frames_toref.data(), nullptr, warp_too ? &warp : nullptr, num_cameras,
        num_cameras - 1, static_cast<int>(frames_toref.size()), 0, 0,
        observations.data(), nullptr, static_cast<int>(observations.size()), 0,
        pool.data(), &model, imagersizes.data(), selections, &constants,
        board.spacing_m, board.grid_width, board.grid_height, false, false);
    if (!std::isfinite(stats.rms_reproj_error__pixels) ||
        stats.rms_reproj_error__pixels < 0.0) {
      throw Error("mrcal_optimize failed (no finite solution)");
    }
    return stats;
  }

  // The covariance of the last Solve as mrcal computes it
  // (doc/uncertainty.org): with J the Jacobian in mrcal's packed state b*
  // and Jo its rows of board corners (regularization is no measurement),
  // Var(b*) = σ² inv(JᵀJ) JoᵀJo inv(JᵀJ), and b = D b*. Each camera keeps
  // the block its projection depends on (MrcalSolveCovariance).
  void Covariances(const mrcal_lensmodel_t& model,
                   const CalibrationBoard& board,
                   std::vector<MrcalCalibration>* cameras) const {
    const int num_frames = static_cast<int>(frames_toref.size());
    const int num_views = static_cast<int>(observations.size());
    const int num_states =
        mrcal_num_states(num_cameras, num_cameras - 1, num_frames, 0, 0,
                         num_views, selections, &model);
    const int num_measurements = mrcal_num_measurements(
        num_views, 0, board.grid_width, board.grid_height, num_cameras,
        num_cameras - 1, num_frames, 0, 0, selections, &model);
    const int num_nonzero =
        _mrcal_num_j_nonzero(num_views, 0, board.grid_width, board.grid_height,
                             num_cameras, num_cameras - 1, num_frames, 0, 0,
                             observations.data(), nullptr, selections, &model);
    std::vector<int> row_starts(num_measurements + 1);
    std::vector<int> columns(num_nonzero);
    std::vector<double> values(num_nonzero);
    std::vector<double> packed(num_states);
    std::vector<double> x(num_measurements);
    cholmod_sparse jt{};  // Jᵀ, i.e. J row by row
    jt.nrow = num_states;
    jt.ncol = num_measurements;
    jt.nzmax = num_nonzero;
    jt.p = row_starts.data();
    jt.i = columns.data();
    jt.x = values.data();
    jt.itype = CHOLMOD_INT;
    jt.xtype = CHOLMOD_REAL;
    jt.dtype = CHOLMOD_DOUBLE;
    jt.sorted = 1;
    jt.packed = 1;
    if (!mrcal_optimizer_callback(
            packed.data(), num_states * sizeof(double), x.data(),
            num_measurements * sizeof(double), &jt, intrinsics.data(),
            extrinsics_fromref.data(), frames_toref.data(), nullptr,
            selections.do_optimize_calobject_warp ? &warp : nullptr,
            num_cameras, num_cameras - 1, num_frames, 0, 0, observations.data(),
            nullptr, num_views, 0, pool.data(), &model, imagersizes.data(),
            selections, &constants, board.spacing_m, board.grid_width,
            board.grid_height, false)) {
      throw Error("mrcal_optimizer_callback failed on the solution");
    }
    // Copied by columns and back: sorted indices, as Eigen wants them.
    const Eigen::SparseMatrix<double> j_by_columns =
        Eigen::Map<const Eigen::SparseMatrix<double, Eigen::RowMajor>>(
            num_measurements, num_states, num_nonzero, row_starts.data(),
            columns.data(), values.data());
    const Eigen::SparseMatrix<double, Eigen::RowMajor> j = j_by_columns;
    const Eigen::SimplicialLLT<Eigen::SparseMatrix<double>> jtj(
        Eigen::SparseMatrix<double>(j_by_columns.transpose() * j_by_columns));
    if (jtj.info() != Eigen::Success) {
      throw Error(
          "calibration: JᵀJ of the solution is singular: the board views do "
          "not determine every parameter, so there is no uncertainty");
    }
    const int num_board_rows = mrcal_num_measurements_boards(
        num_views, board.grid_width, board.grid_height);
    const Eigen::SparseMatrix<double> jo = j.topRows(num_board_rows);
    const Eigen::SparseMatrix<double> jotjo = jo.transpose() * jo;
    Eigen::VectorXd scale = Eigen::VectorXd::Ones(num_states);
    mrcal_unpack_solver_state_vector(scale.data(), num_cameras, num_cameras - 1,
                                     num_frames, 0, 0, selections, &model);

    // σ as mrcal's projection_uncertainty() infers it: the standard
    // deviation of the inlier corners' residual coordinates.
    double sum = 0.0;
    double sum_squares = 0.0;
    int count = 0;
    for (size_t k = 0; k < pool.size(); ++k) {
      if (pool[k].z <= 0.0) continue;
      for (int xy = 0; xy < 2; ++xy) {
        sum += x[2 * k + xy];
        sum_squares += x[2 * k + xy] * x[2 * k + xy];
        ++count;
      }
    }
    const double mean = sum / std::max(count, 1);
    const double sigma = std::sqrt(
        std::max(sum_squares / std::max(count, 1) - mean * mean, 0.0));

    const int num_intrinsics = mrcal_lensmodel_num_params(&model);
    if (mrcal_num_intrinsics_optimization_params(selections, &model) !=
        num_intrinsics) {
      throw Error("calibration: the final solve must move every intrinsic");
    }
    for (int c = 0; c < num_cameras; ++c) {
      std::vector<int> states;
      const auto append = [&](int first, int count) {
        for (int i = 0; i < count; ++i) states.push_back(first + i);
      };
      append(mrcal_state_index_intrinsics(c, num_cameras, num_cameras - 1,
                                          num_frames, 0, 0, num_views,
                                          selections, &model),
             num_intrinsics);
      if (c > 0) {
        append(mrcal_state_index_extrinsics(c - 1, num_cameras, num_cameras - 1,
                                            num_frames, 0, 0, num_views,
                                            selections, &model),
               6);
      }
      append(
          mrcal_state_index_frames(0, num_cameras, num_cameras - 1, num_frames,
                                   0, 0, num_views, selections, &model),
          6 * num_frames);
      const int size = static_cast<int>(states.size());
      Eigen::MatrixXd selector = Eigen::MatrixXd::Zero(num_states, size);
      Eigen::VectorXd block_scale(size);
      for (int i = 0; i < size; ++i) {
        selector(states[i], i) = 1.0;
        block_scale(i) = scale(states[i]);
      }
      const Eigen::MatrixXd rows = jtj.solve(selector);  // inv(JᵀJ) columns
      MrcalSolveCovariance& covariance = (*cameras)[c].covariance;
      covariance.state =
          (rows.transpose() * (jotjo * rows))
              .cwiseProduct(block_scale * block_scale.transpose());
      covariance.observed_pixel_sigma = sigma;
      covariance.has_rt_cam_from_ref = c > 0;
      if (c > 0) {
        const mrcal_pose_t& pose = extrinsics_fromref[c - 1];
        covariance.rt_cam_from_ref << pose.r.x, pose.r.y, pose.r.z, pose.t.x,
            pose.t.y, pose.t.z;
      }
      covariance.rt_ref_from_frame.clear();
      for (const mrcal_pose_t& pose : frames_toref) {
        covariance.rt_ref_from_frame.emplace_back();
        covariance.rt_ref_from_frame.back() << pose.r.x, pose.r.y, pose.r.z,
            pose.t.x, pose.t.y, pose.t.z;
      }
    }
  }
};

// The board's pose in one view by PnP of the stereographic seed's
// unprojections (normalised, z = 1), as mrcal's seed does; false if fewer
// than 4 corners unproject.
bool SeedBoardPose(const BoardObservation& observation,
                   const std::vector<cv::Point3d>& object_points,
                   const double* seed_intrinsics, Rigid3d* cam_from_board) {
  mrcal_lensmodel_t stereographic;
  stereographic.type = MRCAL_LENSMODEL_STEREOGRAPHIC;
  std::vector<cv::Point3d> seen_in_board;
  std::vector<cv::Point2d> normalised;
  for (size_t k = 0; k < object_points.size(); ++k) {
    if (observation.weights[k] <= 0.0) continue;
    const mrcal_point2_t q{
        {observation.pixels[k].x(), observation.pixels[k].y()}};
    mrcal_point3_t v;
    if (!mrcal_unproject(&v, &q, 1, &stereographic, seed_intrinsics) ||
        !(v.z > 0.0)) {
      continue;
    }
    seen_in_board.push_back(object_points[k]);
    normalised.emplace_back(v.x / v.z, v.y / v.z);
  }
  if (seen_in_board.size() < 4) return false;  // mrcal drops such views too
  cv::Mat rvec;
  cv::Mat tvec;
  if (!cv::solvePnP(seen_in_board, normalised, cv::Mat::eye(3, 3, CV_64F),
                    cv::Mat(), rvec, tvec)) {
    return false;
  }
  mrcal_pose_t pose;
  for (int i = 0; i < 3; ++i) {
    pose.r.xyz[i] = rvec.at<double>(i);
    pose.t.xyz[i] = tvec.at<double>(i);
  }
  *cam_from_board = RigidFromPose(pose);
  return true;
}

// Camera c's pose relative to camera 0 from the frames both saw: the
// quaternion mean of cam_c_from_cam0 over them, and the mean translation.
Rigid3d SeedCameraFromReference(const std::vector<View>& views, int camera) {
  std::map<int, const View*> reference;
  for (const View& view : views) {
    if (view.camera == 0) reference[view.frame] = &view;
  }
  Eigen::Vector4d rotation_sum = Eigen::Vector4d::Zero();
  Eigen::Vector3d translation_sum = Eigen::Vector3d::Zero();
  int count = 0;
  for (const View& view : views) {
    const auto it = reference.find(view.frame);
    if (view.camera != camera || it == reference.end()) continue;
    const Rigid3d c_from_0 =
        Compose(view.cam_from_board, it->second->cam_from_board.Inverse());
    Eigen::Vector4d q = c_from_0.rotation.normalized().coeffs();
    if (count > 0 && q.dot(rotation_sum) < 0.0) q = -q;
    rotation_sum += q;
    translation_sum += c_from_0.translation;
    ++count;
  }
  if (count == 0) {
    throw ErrorAt("calibration: camera ", camera,
                  " shares no board view (frame) with camera 0, so the rig "
                  "cannot be tied together");
  }
  Rigid3d c_from_0;
  c_from_0.rotation = Eigen::Quaterniond(rotation_sum.normalized());
  c_from_0.translation = translation_sum / count;
  return c_from_0;
}

}  // namespace

void MrcalCalibrationOptions::Check() const {
  LensModel(lens_model);
  if (!(focal_px > 0.0) || !std::isfinite(focal_px)) {
    throw Error("calibration: focal_px (the seed focal length) must be > 0");
  }
  if (image_width <= 0 || image_height <= 0) {
    throw Error("calibration: image_width and image_height must be > 0");
  }
}

// CalibrateRigWithMrcal on a board of evenly spaced corners.
static MrcalRigCalibration CalibrateRigOnRegularBoard(
    const std::vector<RigCameraViews>& cameras, const CalibrationBoard& board,
    const MrcalCalibrationOptions& options) {
  options.Check();
  if (cameras.empty()) throw Error("calibration: no camera");
  const mrcal_lensmodel_t model = LensModel(options.lens_model);
  const int num_params = mrcal_lensmodel_num_params(&model);
  const std::vector<Eigen::Vector3d> corners = board.CornersInBoard();
  const int num_corners = board.NumCorners();
  const int num_cameras = static_cast<int>(cameras.size());
  std::vector<cv::Point3d> object_points;
  for (const Eigen::Vector3d& corner : corners) {
    object_points.emplace_back(corner.x(), corner.y(), corner.z());
  }

  // The stereographic seed (mrcal's seed_stereographic): f, centre at the
  // image's middle in mrcal's pixel convention.
  const std::vector<double> seed = {options.focal_px, options.focal_px,
                                    (options.image_width - 1) / 2.0,
                                    (options.image_height - 1) / 2.0};
  std::vector<View> views;
  std::map<int, int> frame_index;  // caller's frame -> mrcal's
  for (int c = 0; c < num_cameras; ++c) {
    const RigCameraViews& camera = cameras[c];
    if (camera.frames.size() != camera.views.size()) {
      throw ErrorAt("calibration: camera ", c, " has ", camera.views.size(),
                    " views but ", camera.frames.size(), " frame numbers");
    }
    std::set<int> seen_frames;
    for (size_t i = 0; i < camera.views.size(); ++i) {
      const BoardObservation& observation = camera.views[i];
      if (!observation.Found()) continue;
      if (static_cast<int>(observation.pixels.size()) != num_corners) {
        throw ErrorAt(observation.image, ": ", observation.pixels.size(),
                      " corners, but the board ", board.ToString(), " has ",
                      num_corners);
      }
      if (!seen_frames.insert(camera.frames[i]).second) {
        throw ErrorAt(observation.image, ": camera ", c,
                      " has a second view of frame ", camera.frames[i]);
      }
      View view;
      view.camera = c;
      view.frame = camera.frames[i];
      view.source = i;
      if (!SeedBoardPose(observation, object_points, seed.data(),
                         &view.cam_from_board)) {
        continue;
      }
      views.push_back(view);
    }
  }
  // mrcal wants the observations ordered by frame.
  std::stable_sort(
      views.begin(), views.end(), [](const View& a, const View& b) {
        return a.frame != b.frame ? a.frame < b.frame : a.camera < b.camera;
      });

  Problem problem;
  problem.num_cameras = num_cameras;
  for (int c = 0; c < num_cameras; ++c) {
    problem.intrinsics.insert(problem.intrinsics.end(), seed.begin(),
                              seed.end());
    problem.imagersizes.push_back(options.image_width);
    problem.imagersizes.push_back(options.image_height);
  }
  std::vector<Rigid3d> cam_from_ref(num_cameras);
  for (int c = 1; c < num_cameras; ++c) {
    cam_from_ref[c] = SeedCameraFromReference(views, c);
    problem.extrinsics_fromref.push_back(PoseFromRigid(cam_from_ref[c]));
  }

  MrcalRigCalibration result;
  result.cameras.resize(num_cameras);
  std::vector<int> views_per_camera(num_cameras, 0);
  for (View& view : views) {
    const auto [it, inserted] = frame_index.emplace(
        view.frame, static_cast<int>(problem.frames_toref.size()));
    if (inserted) {
      problem.frames_toref.push_back(PoseFromRigid(
          Compose(cam_from_ref[view.camera].Inverse(), view.cam_from_board)));
    }
    problem.observations.push_back(
        {{view.camera, view.camera - 1}, it->second});
    const BoardObservation& observation =
        cameras[view.camera].views[view.source];
    MrcalCalibration& camera = result.cameras[view.camera];
    for (int k = 0; k < num_corners; ++k) {
      mrcal_point3_t point;
      point.x = observation.pixels[k].x();
      point.y = observation.pixels[k].y();
      point.z = observation.weights[k] > 0.0 ? observation.weights[k] : -1.0;
      problem.pool.push_back(point);
      problem.found.push_back(observation.weights[k] > 0.0);
      camera.num_corners_observed += observation.weights[k] > 0.0;
    }
    camera.images.push_back(observation.image);
    ++views_per_camera[view.camera];
  }

  // Enough data: 3 views a camera at least (one view cannot tell focal
  // length from distance), and more measurements than unknowns.
  int corners_observed = 0;
  for (int c = 0; c < num_cameras; ++c) {
    corners_observed += result.cameras[c].num_corners_observed;
    if (views_per_camera[c] < 3) {
      throw ErrorAt("calibration: camera ", c, ": ", views_per_camera[c],
                    " board views are too few for ", options.lens_model,
                    ": need at least 3");
    }
  }
  const int unknowns = 6 * static_cast<int>(problem.frames_toref.size()) +
                       6 * (num_cameras - 1) + num_cameras * num_params;
  if (corners_observed < unknowns) {
    throw ErrorAt("calibration: ", views.size(), " board views with ",
                  corners_observed, " corners are too few for ",
                  options.lens_model, " (", num_params,
                  " intrinsics a camera): need twice as many corner "
                  "coordinates as unknowns (",
                  2 * unknowns, ")");
  }

  // mrcal-calibrate-cameras' stages.
  mrcal_lensmodel_t stereographic;
  stereographic.type = MRCAL_LENSMODEL_STEREOGRAPHIC;
  problem.Solve(stereographic, false, false, false, false, false, board);
  problem.Solve(stereographic, true, false, false, false, false, board);
  std::vector<double> expanded;
  for (int c = 0; c < num_cameras; ++c) {
    expanded.insert(expanded.end(), problem.intrinsics.begin() + 4 * c,
                    problem.intrinsics.begin() + 4 * c + 4);
    expanded.resize(expanded.size() + num_params - 4, 0.0);
  }
  problem.intrinsics = expanded;
  const int num_missing =
      static_cast<int>(problem.pool.size()) - corners_observed;
  mrcal_stats_t stats = problem.Solve(model, true, true, true,
                                      options.outlier_rejection, false, board);
  if (options.calobject_warp) {
    stats = problem.Solve(model, true, true, options.regularization,
                          options.outlier_rejection, true, board);
  } else if (!options.regularization) {
    stats = problem.Solve(model, true, true, false, options.outlier_rejection,
                          false, board);
  }
  // The RMS is the caller's (InlierRmsPerCoordinate), not mrcal's.
  result.num_outliers = stats.Noutliers - num_missing;
  result.cam_from_rig.assign(num_cameras, Rigid3d());
  for (int c = 1; c < num_cameras; ++c) {
    result.cam_from_rig[c] = RigidFromPose(problem.extrinsics_fromref[c - 1]);
  }
  for (int c = 0; c < num_cameras; ++c) {
    MrcalCalibration& camera = result.cameras[c];
    camera.lens_model = options.lens_model;
    camera.image_width = options.image_width;
    camera.image_height = options.image_height;
    camera.intrinsics.assign(problem.intrinsics.begin() + c * num_params,
                             problem.intrinsics.begin() + (c + 1) * num_params);
    camera.calobject_warp = {problem.warp.x2, problem.warp.y2};
  }
  problem.Covariances(model, board, &result.cameras);

  // Residuals through mrcal's projection, the board warped as mrcal warps it.
  for (size_t o = 0; o < problem.observations.size(); ++o) {
    const int c = problem.observations[o].icam.intrinsics;
    MrcalCalibration& camera = result.cameras[c];
    const Rigid3d cam_from_board = Compose(
        result.cam_from_rig[c],
        RigidFromPose(problem.frames_toref[problem.observations[o].iframe]));
    const Eigen::Matrix3d rotation = cam_from_board.RotationMatrix();
    camera.cam_from_board.push_back(cam_from_board);
    std::vector<bool> found;
    std::vector<Eigen::Vector2d> residuals;
    std::vector<bool> outliers;
    for (int k = 0; k < num_corners; ++k) {
      const int i = k % board.grid_width;
      const int j = k / board.grid_width;
      const double xr = static_cast<double>(i) / (board.grid_width - 1);
      const double yr = static_cast<double>(j) / (board.grid_height - 1);
      Eigen::Vector3d point = corners[k];
      point.z() += problem.warp.x2 * 4.0 * xr * (1.0 - xr) +
                   problem.warp.y2 * 4.0 * yr * (1.0 - yr);
      const Eigen::Vector3d in_cam =
          rotation * point + cam_from_board.translation;
      const mrcal_point3_t p{{in_cam.x(), in_cam.y(), in_cam.z()}};
      mrcal_point2_t q;
      mrcal_project(&q, nullptr, nullptr, &p, 1, &model,
                    camera.intrinsics.data());
      const size_t entry = o * num_corners + k;
      const mrcal_point3_t& seen = problem.pool[entry];
      found.push_back(problem.found[entry]);
      residuals.emplace_back(q.x - seen.x, q.y - seen.y);
      // Missing on input or thrown out by the solve: both have weight < 0;
      // only the second is an outlier.
      const bool outlier = seen.z <= 0.0 && problem.found[entry];
      outliers.push_back(outlier);
      camera.num_outliers += outlier;
    }
    camera.found.push_back(std::move(found));
    camera.residuals_px.push_back(std::move(residuals));
    camera.outliers.push_back(std::move(outliers));
  }
  return result;
}

// The RMS of the inlier corners' residuals per coordinate. mrcal's own
// divides by every board point, found or not, which on an AprilGrid's
// lattice (mostly points that are no corner) would read 7x too small.
double InlierRmsPerCoordinate(const MrcalRigCalibration& result) {
  double sum_squares = 0.0;
  int count = 0;
  for (const MrcalCalibration& camera : result.cameras) {
    for (size_t v = 0; v < camera.residuals_px.size(); ++v) {
      for (size_t k = 0; k < camera.residuals_px[v].size(); ++k) {
        if (!camera.found[v][k] || camera.outliers[v][k]) continue;
        sum_squares += camera.residuals_px[v][k].squaredNorm();
        ++count;
      }
    }
  }
  return std::sqrt(sum_squares / std::max(2 * count, 1));
}

MrcalRigCalibration CalibrateRigWithMrcal(
    const std::vector<RigCameraViews>& cameras, const CalibrationBoard& board,
    const MrcalCalibrationOptions& options) {
  MrcalRigCalibration result;
  if (board.IsRegularGrid()) {
    result = CalibrateRigOnRegularBoard(cameras, board, options);
  } else {
    // mrcal sees the corners on their lattice, the other points missing;
    // the results come back per corner.
    const BoardLattice lattice = MrcalLattice(board);
    std::vector<RigCameraViews> on_lattice = cameras;
    for (RigCameraViews& camera : on_lattice) {
      for (BoardObservation& view : camera.views) {
        if (view.Found()) view = OnLattice(view, lattice);
      }
    }
    result = CalibrateRigOnRegularBoard(on_lattice, lattice.regular, options);
    for (MrcalCalibration& camera : result.cameras) {
      for (size_t v = 0; v < camera.residuals_px.size(); ++v) {
        std::vector<bool> found;
        std::vector<Eigen::Vector2d> residuals;
        std::vector<bool> outliers;
        for (const int point : lattice.point_of_corner) {
          found.push_back(camera.found[v][point]);
          residuals.push_back(camera.residuals_px[v][point]);
          outliers.push_back(camera.outliers[v][point]);
        }
        camera.found[v] = std::move(found);
        camera.residuals_px[v] = std::move(residuals);
        camera.outliers[v] = std::move(outliers);
      }
    }
  }
  result.rms_px = InlierRmsPerCoordinate(result);
  for (MrcalCalibration& camera : result.cameras) camera.rms_px = result.rms_px;
  return result;
}

MrcalCalibration CalibrateWithMrcal(
    const std::vector<BoardObservation>& observations,
    const CalibrationBoard& board, const MrcalCalibrationOptions& options) {
  RigCameraViews camera;
  camera.views = observations;
  for (size_t i = 0; i < observations.size(); ++i) {
    camera.frames.push_back(static_cast<int>(i));
  }
  return CalibrateRigWithMrcal({camera}, board, options).cameras[0];
}

std::string FormatCameraModel(const std::string& lens_model,
                              const std::vector<double>& intrinsics,
                              int image_width, int image_height,
                              const Rigid3d& cam_from_rig,
                              const std::vector<std::string>& comments) {
  const mrcal_pose_t extrinsics = PoseFromRigid(cam_from_rig);
  std::ostringstream text;
  for (const std::string& comment : comments) text << "# " << comment << "\n";
  text << "{\n    'lensmodel':  '" << lens_model << "',\n"
       << "    # intrinsics are fx,fy,cx,cy,distortion0,distortion1,....\n"
       << "    'intrinsics': [";
  for (const double value : intrinsics) text << fmt::format(" {:.17g},", value);
  text << " ],\n"
       << "    # extrinsics are rt_fromref\n"
       << "    'extrinsics': [";
  for (const mrcal_point3_t* part : {&extrinsics.r, &extrinsics.t}) {
    for (int i = 0; i < 3; ++i) text << fmt::format(" {:.17g},", part->xyz[i]);
  }
  text << " ],\n"
       << "    'imagersize': [ " << image_width << ", " << image_height
       << ", ],\n}\n";
  return text.str();
}

MrcalCameraModel ReadCameraModel(const std::string& path) {
  const std::string text = ReadFileToString(path);
  mrcal_cameramodel_t* parsed = mrcal_read_cameramodel_string(
      text.c_str(), static_cast<int>(text.size()));
  if (parsed == nullptr) {
    throw ErrorAt(path,
                  ": not a .cameramodel mrcal can read (mrcal's parser "
                  "refused it; see its messages above)");
  }
  std::unique_ptr<mrcal_cameramodel_t, void (*)(mrcal_cameramodel_t*)> owner(
      parsed,
      [](mrcal_cameramodel_t* model) { mrcal_free_cameramodel(&model); });
  MrcalCameraModel model;
  char name[256];
  if (!mrcal_lensmodel_name(name, sizeof(name), &parsed->lensmodel)) {
    throw ErrorAt(path, ": its lens model has no name mrcal knows");
  }
  model.lens_model = name;
  const int num_params = mrcal_lensmodel_num_params(&parsed->lensmodel);
  model.intrinsics.assign(parsed->intrinsics, parsed->intrinsics + num_params);
  model.image_width = static_cast<int>(parsed->imagersize[0]);
  model.image_height = static_cast<int>(parsed->imagersize[1]);
  for (int i = 0; i < 6; ++i) model.rt_cam_ref(i) = parsed->rt_cam_ref[i];
  return model;
}

}  // namespace uw
