// Laser directions from mission data (thesis ch. 4 §5.3, ch. 6 §6.6; ch4
// spec §6): the laser origins are known from the mounting, only the
// directions moved at a re-mounting, and there are no calibration images.
// Each detected spot of a localized image is ray cast onto ONE model's
// surface and expressed in the image's camera frame; the points of a laser
// lie on the line s O + t v, s the model's unknown scale. A line fitted to
// them gives v, which carries no scale: any model of constant scale serves,
// but points of two models (two scales) must never be mixed. The
// direction's covariance comes from a Monte Carlo over the spots'
// covariances (re-cast, re-fit); the fit is checked by the distance in the
// image between each spot and the image of the calibrated beam, which does
// not depend on the model's scale either.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "colmap_plugins/scene/model.h"
#include "common/mesh/ray_caster.h"
#include "laserscale/laser_setup.h"

namespace uw {

// One detected spot of the laser in one localized image.
struct MissionSpot {
  std::string image;
  int dive = 1;
  Camera camera;           // the model's camera of the image
  Rigid3d cam_from_world;  // model units and frame
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();  // COLMAP convention
  Eigen::Matrix2d covariance_px = Eigen::Matrix2d::Zero();
};

struct MissionCalibrationOptions {
  // Monte Carlo repetitions for the direction's covariance (the thesis: 1000).
  int num_iterations = 1000;
  uint64_t seed = 0;
  // RANSAC: a point is an inlier when its distance from the line, seen from
  // its camera, is at most this many pixels (scale-free).
  double inlier_px = 3.0;
  int ransac_iterations = 1000;
  // At least this many inlier spots, and the farthest at least this many
  // times as deep as the nearest: the direction's lever arm.
  int min_spots = 5;
  double min_depth_ratio = 1.3;
  int num_threads = 0;  // <= 0: all

  void Check() const;
};

struct MissionLaserCalibration {
  // The a-priori origin (and its covariance) with the fitted direction and
  // the Monte Carlo's covariance of it (rank 2, across the beam).
  Laser laser;
  // Per input spot: its point in its camera frame (model units) when the
  // ray met the surface, whether the line fit kept it, else why not.
  std::vector<Eigen::Vector3d> points_in_cam;
  std::vector<bool> inliers;
  std::vector<std::string> problems;
  int num_inliers = 0;
  double min_depth = 0.0;  // inliers' depths, model units
  double max_depth = 0.0;
  double angle_from_a_priori_deg = 0.0;
  double sigma_deg = 0.0;       // sqrt of the direction covariance's trace
  int num_iterations_used = 0;  // Monte Carlo fits that succeeded
  // Distance in the image between each inlier spot (undistorted) and the
  // image of the calibrated beam: RMS per dive and overall (px).
  struct DiveRms {
    int dive = 1;
    int num_spots = 0;
    double rms_px = 0.0;
  };
  std::vector<DiveRms> rms_by_dive;
  double rms_px = 0.0;
};

// Throws uw::Error naming the laser when fewer than min_spots spots meet
// the surface and line up, or when they span too little depth.
MissionLaserCalibration CalibrateLaserFromMission(
    const Laser& a_priori, const RayCaster& caster,
    const std::vector<MissionSpot>& spots,
    const MissionCalibrationOptions& options);

// The distance (px, at the camera's focal length) between a spot, once
// undistorted, and the image of the beam origin + t direction: the line
// K^-T (origin x direction), the same for origin and s origin.
double BeamImageDistancePx(const Camera& camera, const Laser& laser,
                           const Eigen::Vector2d& spot_px);

}  // namespace uw
