// mrcal's projection uncertainty (mrcal 2.2: doc/uncertainty.org,
// mrcal.projection_uncertainty() and the map mrcal-show-projection-uncertainty
// draws): how far, 1σ, the calibration's own noise moves the projection of
// a point fixed to the camera's housing.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "calib/mrcal_calibration.h"

namespace uw {

// Var(q) (pixels²) of the projection of `point_in_cam` (the camera's frame,
// the board's units) through the solve's uncertain intrinsics, camera pose
// and board poses, as mrcal 2.2 propagates it ("mean-frames"): the point
// goes to the rig's frame, into every board's frame, back through each
// board's perturbed pose, the mean of those, then through the perturbed
// camera pose and intrinsics: Var(q) = σ² G Var(b) Gᵀ, G = dq/db, σ the
// camera's covariance.observed_pixel_sigma. At infinity only the point's
// direction counts and the poses' translations drop out. Throws uw::Error
// when `camera` has no covariance of the right size.
Eigen::Matrix2d ProjectionCovariance(const MrcalCalibration& camera,
                                     const Eigen::Vector3d& point_in_cam,
                                     bool at_infinity);

// The standard deviation in the worst direction: the square root of the
// larger eigenvalue of `covariance` (mrcal's 'worstdirection-stdev', what
// mrcal-show-projection-uncertainty plots unless --isotropic).
double WorstDirectionStdev(const Eigen::Matrix2d& covariance);

// The worst-direction 1σ at `pixel` (mrcal's convention: (0, 0) is the
// centre of the top-left pixel) for a point `distance` away along its ray
// (the board's units; 0 is infinity). +inf where the pixel does not
// unproject.
double ProjectionUncertaintyAtPixel(const MrcalCalibration& camera,
                                    const Eigen::Vector2d& pixel,
                                    double distance);

struct ProjectionUncertaintyOptions {
  // How far the points are, in the board's units (metres); 0 looks out to
  // infinity, as mrcal-show-projection-uncertainty does unless --distance.
  double distance = 0.0;
  // Samples across and down the image, its edge pixels included (the tool's
  // --gridn).
  int grid_width = 60;
  int grid_height = 40;

  // Throws uw::Error naming the first bad field.
  void Check() const;
};

struct ProjectionUncertaintyMap {
  std::vector<double> x_px;  // the samples' columns, 0 .. width - 1
  std::vector<double> y_px;  // their rows, 0 .. height - 1
  // Worst-direction 1σ, pixels: (row, column) = (y_px[i], x_px[j]); +inf
  // where a pixel does not unproject.
  Eigen::MatrixXd stdev_px;
  double at_centre_px = 0.0;  // at ((width - 1) / 2, (height - 1) / 2)
  double distance = 0.0;      // options.distance
  double observed_pixel_sigma = 0.0;

  double MaxPx() const;  // over the samples
};

// The worst-direction 1σ over a grid of the image, as
// mrcal-show-projection-uncertainty computes it by default.
ProjectionUncertaintyMap MapProjectionUncertainty(
    const MrcalCalibration& camera,
    const ProjectionUncertaintyOptions& options);

}  // namespace uw
