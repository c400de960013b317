// Camera calibration from board observations with mrcal's C library
// (libmrcal 2.2): the solve mrcal-calibrate-cameras runs, driven from C++.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "calib/board.h"
#include "calib/corners_vnl.h"
#include "colmap_plugins/scene/model.h"

namespace uw {

struct MrcalCalibrationOptions {
  // mrcal's lens model name, e.g. LENSMODEL_OPENCV8 (see mrcal's docs).
  std::string lens_model = "LENSMODEL_OPENCV8";
  double focal_px = 0.0;  // seed focal length, pixels (required)
  int image_width = 0;    // pixels (required)
  int image_height = 0;
  // The final solve's terms, as mrcal-calibrate-cameras runs them by default.
  bool regularization = true;
  bool outlier_rejection = true;
  bool calobject_warp = true;

  // Throws uw::Error naming the first bad field.
  void Check() const;
};

// What mrcal's projection_uncertainty() takes from a solve's
// optimization_inputs, for one camera (calib/projection_uncertainty.h).
struct MrcalSolveCovariance {
  // Every board pose of the solve, the rig's frame from the board's, as
  // mrcal's frames_rt_toref: Rodrigues rotation, then translation.
  std::vector<Eigen::Matrix<double, 6, 1>> rt_ref_from_frame;
  // The camera's pose, mrcal's rt_fromref; only cameras 1.. of a rig have
  // one in the solve (camera 0 is the rig's frame).
  bool has_rt_cam_from_ref = false;
  Eigen::Matrix<double, 6, 1> rt_cam_from_ref =
      Eigen::Matrix<double, 6, 1>::Zero();
  // Covariance of (intrinsics, rt_cam_from_ref if any, rt_ref_from_frame in
  // order) per unit variance of the corners' noise.
  Eigen::MatrixXd state;
  // mrcal's estimate of that noise: the standard deviation of the inlier
  // corners' weighted residual coordinates, all cameras (pixels).
  double observed_pixel_sigma = 0.0;
};

struct MrcalCalibration {
  std::string lens_model;
  std::vector<double> intrinsics;  // fx, fy, cx, cy, distortions (mrcal's)
  int image_width = 0;
  int image_height = 0;

  // Per board observation used (images where a board was found, file order).
  std::vector<std::string> images;
  std::vector<Rigid3d> cam_from_board;
  // Per used observation and corner: whether the detector found it (a
  // partial board: an AprilGrid's or ChArUco's), its reprojection residual
  // (pixels, projected minus observed; meaningless when not found), and
  // whether the solve threw it out.
  std::vector<std::vector<bool>> found;
  std::vector<std::vector<Eigen::Vector2d>> residuals_px;
  std::vector<std::vector<bool>> outliers;

  // RMS of the inlier corners' residuals per coordinate (what mrcal reports
  // on a chessboard; mrcal's own figure would count an AprilGrid lattice's
  // empty points too).
  double rms_px = 0.0;
  int num_corners_observed = 0;  // found by the detector
  int num_outliers = 0;          // thrown out by the solve
  Eigen::Vector2d calobject_warp = Eigen::Vector2d::Zero();  // x2, y2 (m)
  MrcalSolveCovariance covariance;
};

// Seeds (stereographic core from focal_px, board poses by PnP of the
// stereographic unprojections, as mrcal's seed_stereographic does) and
// solves in mrcal-calibrate-cameras' stages: geometry, + core, then the
// lens model with regularization and outlier rejection, then the board's
// warp. One camera; images without a board are skipped. Throws uw::Error
// when fewer boards than the lens model needs were found, mrcal fails or
// the solution is not determined (JᵀJ singular: no covariance).
MrcalCalibration CalibrateWithMrcal(
    const std::vector<BoardObservation>& observations,
    const CalibrationBoard& board, const MrcalCalibrationOptions& options);

// One camera of a rig: its images of the board, and for each the frame (the
// instant: views of different cameras with the same frame saw the board in
// one pose).
struct RigCameraViews {
  std::vector<BoardObservation> views;
  std::vector<int> frames;  // parallel to views
};

struct MrcalRigCalibration {
  // Per camera: intrinsics, its views, residuals and outliers; rms_px and
  // calobject_warp are the rig's.
  std::vector<MrcalCalibration> cameras;
  std::vector<Rigid3d> cam_from_rig;  // the rig's frame is camera 0's
  double rms_px = 0.0;
  int num_outliers = 0;
};

// Synchronised cameras that see one board, as mrcal-calibrate-cameras with
// several globs: the intrinsics of each, and their poses. The extrinsics
// are seeded from the frames each camera shares with camera 0 (an error if
// it shares none); the stages are those of CalibrateWithMrcal. All cameras
// have options' image size. An AprilGrid goes to mrcal on its lattice
// (MrcalLattice); residuals and outliers come back per corner.
MrcalRigCalibration CalibrateRigWithMrcal(
    const std::vector<RigCameraViews>& cameras, const CalibrationBoard& board,
    const MrcalCalibrationOptions& options);

// The .cameramodel text mrcal reads (mrcal's Python-dict layout; every
// number to 17 significant digits). `comments` become '#' lines;
// cam_from_rig is written as mrcal's extrinsics (rt_fromref).
std::string FormatCameraModel(const std::string& lens_model,
                              const std::vector<double>& intrinsics,
                              int image_width, int image_height,
                              const Rigid3d& cam_from_rig,
                              const std::vector<std::string>& comments);

struct MrcalCameraModel {
  std::string lens_model;
  std::vector<double> intrinsics;
  int image_width = 0;
  int image_height = 0;
  Eigen::Matrix<double, 6, 1> rt_cam_ref = Eigen::Matrix<double, 6, 1>::Zero();
};

// Reads a .cameramodel with mrcal's own parser. Throws uw::Error naming
// the file.
MrcalCameraModel ReadCameraModel(const std::string& path);

}  // namespace uw
