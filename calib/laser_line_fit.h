// A laser's line in the camera frame from its spots on a calibration board
// at many distances (thesis ch. 3 §2.4 [L2196-L2220]): each spot's ray is
// cut with the board's plane (its pose from its corners), and a line is
// fitted robustly to the 3D points. The result is what lasers.json stores:
// the origin where the line meets the camera plane Π (z = 0), the unit
// direction, and their covariances.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "colmap_plugins/scene/model.h"
#include "laserscale/laser_setup.h"

namespace uw {

// One spot of the laser on the board in one image.
struct LaserBoardSpot {
  std::string image;
  Rigid3d cam_from_board;  // the board's pose (z = 0 is its surface)
  Eigen::Vector2d pixel;   // the spot's centre, COLMAP pixel convention
};

struct LaserLineFitOptions {
  // RANSAC on pairs of points: a point further than this from the line
  // through two others is an outlier (metres; a bad spot or board pose).
  double inlier_distance_m = 0.005;
  int ransac_iterations = 500;
  uint64_t seed = 0;
  // Spots must span at least this range of depths (the direction's
  // lever arm) and come from at least min_distances images.
  double min_depth_span_m = 0.5;
  int min_distances = 3;

  void Check() const;
};

struct LaserLineFit {
  Laser laser;  // name, origin_in_cam (z = 0), direction_in_cam, covariances
  std::vector<Eigen::Vector3d> points_in_cam;  // per spot, in input order
  std::vector<bool> inliers;
  double rms_distance_m = 0.0;  // inliers' distance from the line
};

// The robust line fit both calibrations share, on points in a camera frame
// (z forward, any unit). RANSAC on pairs at least min_pair_depth_gap apart
// in depth: a point is an inlier of the line through a pair if its distance
// from it is at most tolerance[k]. Then x = Ox + a z, y = Oy + b z by least
// squares on the inliers weighted by 1/z^2 (a point's error grows with its
// depth), the residual variance estimated from the data (2 n - 4 degrees of
// freedom): `laser` gets the origin on z = 0, the unit direction (z > 0) and
// their covariances. The direction does not change when all points are
// scaled. Needs >= 3 points; the caller checks the inliers' depth span.
struct RobustLine {
  Laser laser;
  std::vector<bool> inliers;
  int num_inliers = 0;
  double rms_distance = 0.0;  // inliers' distance from the line
};
// The least-squares part alone, on all of `points_in_cam` (>= 3, z > 0).
RobustLine FitLineByDepth(const std::vector<Eigen::Vector3d>& points_in_cam);
RobustLine FitRobustLine(const std::vector<Eigen::Vector3d>& points_in_cam,
                         const std::vector<double>& tolerance,
                         double min_pair_depth_gap, int ransac_iterations,
                         uint64_t seed);

// Fits x = Ox + a z, y = Oy + b z to the RANSAC inliers by least squares
// weighted by 1/z^2 (a point's error grows with its depth); the covariances
// are those of the fit, its residual variance estimated from the data
// (2 n - 4 degrees of freedom). Throws uw::Error naming the
// laser for too few spots or depths, a ray parallel to a board, or a board
// behind the camera.
LaserLineFit FitLaserLine(const std::string& name, const Camera& camera,
                          const std::vector<LaserBoardSpot>& spots,
                          const LaserLineFitOptions& options);

// Several lasers whose spots are not told apart (each image's spots in any
// order): the line with the most spots is a laser, its inliers leave, and
// again, num_lasers times (sequential RANSAC). The lasers are ordered and
// named L0, L1, ... by the angle of their origin around the optical axis,
// from +x (image right) towards +y (down). Throws uw::Error naming the
// laser that could not be fitted.
std::vector<LaserLineFit> FitLaserLines(
    const Camera& camera, const std::vector<LaserBoardSpot>& spots,
    int num_lasers, const LaserLineFitOptions& options);

}  // namespace uw
