// A synthetic mission for the laser calibration's tests: a rough sea floor,
// downward views at many altitudes, and the spots of a laser set-up's true
// beams on it with pixel noise. Test support only.
#pragma once

#include <vector>

#include "calib/laser_mission_calibration.h"
#include "common/mesh/mesh.h"
#include "common/mesh/ray_caster.h"
#include "laserscale/laser_poses_io.h"
#include "laserscale/laser_setup.h"

namespace uw::testing_mission {

// SIMPLE_RADIAL 1024 x 768, f 850 px, k -0.04: the survey camera.
Camera SurveyCamera();

// The angle between two directions, degrees (atan2: exact near 0).
double AngleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b);

// A rough sea floor (metres, z up; times `scale`): 0.3 m swells and 0.1 m
// ripples over 14 x 14 m, faces counter-clockwise seen from the water.
TriangleMesh Floor(double scale);

struct Mission {
  std::vector<Rigid3d> cam_from_world;          // metres
  std::vector<std::vector<MissionSpot>> spots;  // per laser, model scale 1
};

// `num_images` downward views from 1.5 m to max_altitude_m above the floor,
// tilted up to 8 deg; each laser's spot where its true beam meets the
// floor, with sigma_px noise (and that covariance). The first half is dive
// 1, the rest dive 2. Image i is named "L<i>.png".
Mission MakeMission(const RayCaster& floor, const LaserSetup& truth,
                    int num_images, double sigma_px, uint64_t seed,
                    double max_altitude_m = 4.5);

// The mission's images localized in a model of scale k (the floor `floor`
// is that model's): inliers are floor points on a 150 px grid of pixels.
std::vector<LocalizedImage> Localized(const RayCaster& floor,
                                      const Mission& mission, double k);

}  // namespace uw::testing_mission
