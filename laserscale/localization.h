// Localization of one image against an existing model (ch4 spec §2.2): its
// features matched to the model's 3D points give 2D-3D correspondences; a
// robust PnP finds the pose and the inliers; a refinement with the 3D points
// and the camera fixed minimises the inliers' reprojection error. The RMS of
// that error is the feature noise the Monte Carlo re-samples (§4.1).
//
// PnP: OpenCV's USAC with MAGSAC++ scoring and its P3P minimal solver on
// undistorted rays; MAGSAC++ marginalises over the noise scale as
// AC-RANSAC does, so a wrong `max_error_px` costs accuracy only mildly.
// Refinement: Levenberg-Marquardt on the six pose parameters with the
// COLMAP camera model's exact Jacobian. Both are deterministic: the same
// input gives the same pose on any thread count.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "colmap_plugins/scene/model.h"

namespace uw {

struct Correspondence2D3D {
  Eigen::Vector2d pixel;           // COLMAP pixel convention
  Eigen::Vector3d point_in_world;  // model units and frame
  // The model's point, when known: how the Monte Carlo finds the point's
  // draws of the model's covariance (samples.bin).
  point3D_t point3D_id = kInvalidPoint3DId;
};

struct LocalizationOptions {
  // Inlier threshold of the robust PnP and of the final inlier set (px).
  double max_error_px = 4.0;
  int max_ransac_iterations = 10000;
  double ransac_confidence = 0.9999;
  // Fewer inliers than this is a failed localization.
  int min_num_inliers = 15;
  int max_refine_iterations = 50;
  uint64_t seed = 0;

  // Throws uw::Error naming the offending field.
  void Check() const;
};

struct Localization {
  bool success = false;
  std::string problem;  // why it failed; empty on success
  Rigid3d cam_from_world;
  std::vector<int> inliers;  // indices into the correspondences, ascending
  // RMS of the inliers' reprojection error per image axis (px): the sigma
  // of isotropic Gaussian feature noise that explains it, with the six pose
  // parameters' degrees of freedom removed.
  double rms_error_px = 0.0;
};

Localization LocalizeImage(const Camera& camera,
                           const std::vector<Correspondence2D3D>& matches,
                           const LocalizationOptions& options);

// Levenberg-Marquardt on cam_from_world alone, the points and the camera
// fixed, over matches[indices] (all matches when `indices` is empty).
// Stops when a step changes the cost by < 1e-12 relative or moves the pose
// by < 1e-12; returns false (and leaves *cam_from_world unchanged) if a
// point lies behind the camera or the normal equations are singular.
// Allocation-free: the Monte Carlo calls it thousands of times per image.
bool RefinePose(const Camera& camera,
                const std::vector<Correspondence2D3D>& matches,
                const std::vector<int>& indices, int max_iterations,
                Rigid3d* cam_from_world);

// The Monte Carlo's fast re-localization: when every observed pixel moves
// by a small offset, the refined pose moves by one Gauss-Newton step from
// the nominal pose with the nominal Jacobian J (left increment, as in
// RefinePose):  xi = -(J^T J)^-1 J^T (r0 - offsets).  Exact to first order
// in the offsets; the feature noise of a localization (~1 px over ~1000
// points) moves a pose by ~1e-4 rad, where the second order is ~1e-8 of it.
// Costs one 6 x 2n product per call instead of a refinement's repeated
// reprojections of every point.
class LinearizedPose {
 public:
  // Throws uw::Error if a match is behind the camera or J^T J is singular.
  LinearizedPose(const Camera& camera,
                 const std::vector<Correspondence2D3D>& matches,
                 const Rigid3d& cam_from_world);

  // offsets: (dx0, dy0, dx1, dy1, ...) px, one pair per match.
  Rigid3d Perturbed(const Eigen::VectorXd& pixel_offsets) const;
  // The offsets' step applied to another refined pose of the same image
  // (the pose in a draw of the model, whose Jacobian differs from the
  // nominal one to second order only).
  Rigid3d PerturbedFrom(const Rigid3d& refined,
                        const Eigen::VectorXd& pixel_offsets) const;

 private:
  Rigid3d nominal_;
  Eigen::Matrix<double, 6, Eigen::Dynamic> gain_;  // (J^T J)^-1 J^T
  Eigen::Matrix<double, 6, 1> step_at_nominal_;    // -gain r0
};

// Per-axis RMS reprojection error of matches[indices] with dof = 2n - 6.
double PoseRmsErrorPx(const Camera& camera,
                      const std::vector<Correspondence2D3D>& matches,
                      const std::vector<int>& indices,
                      const Rigid3d& cam_from_world);

}  // namespace uw
