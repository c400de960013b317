// Camera pose priors from navigation: the vehicle's pose from nav.csv,
// taken at the time each image was shot (interpolated between the log's
// samples when needed), through the camera's mount, lever arm and boresight
// and, for the cameras of a rig, through the rig's calibration.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "colmap_plugins/nav/camera_mount.h"
#include "colmap_plugins/nav/image_times.h"
#include "colmap_plugins/nav/nav_csv.h"
#include "colmap_plugins/nav/rig_config.h"

namespace uw {

// How a prior's navigation was obtained.
enum class NavSampling {
  kExact,         // a row of the log at the image's navigation time
  kInterpolated,  // between the two rows of its dive around that time
  kExtrapolated,  // beyond the first or last row of its dive
};

struct CameraPrior {
  std::string image_name;
  int dive = 1;
  double time_s = 0.0;  // navigation time: image time + time offset
  NavSampling sampling = NavSampling::kExact;
  // Camera centre in the world, m.
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  // m²: the vehicle's (diagonal, world axes) plus the attitude error carried
  // through the lever arm, [l]x Σ_w [l]xᵀ with l the camera's offset from
  // the vehicle reference point in world axes. Its correlation with the
  // rotation error below is not kept.
  // A log without roll and pitch takes them as 0 with
  // NavToCameraOptions::unlogged_roll_pitch_sigma_deg. A log without yaw
  // leaves the lever arm's horizontal part h pointing anywhere: the camera
  // is placed at the vehicle plus the arm's vertical part (the vehicle
  // level, or at its logged roll and pitch), with |h|²/2 added along each
  // horizontal axis.
  Eigen::Matrix3d position_covariance = Eigen::Matrix3d::Zero();
  // Only when the log has roll, pitch and yaw (or heading).
  std::optional<Eigen::Quaterniond> cam_from_world_rotation;
  // Σ_w (rad²) of the world-frame rotation error w, R_wc_true = Exp(w) *
  // R_wc_prior, from the roll/pitch/yaw sigmas through the Euler-angle
  // Jacobian (attitude.h). Mount, boresight and rig add nothing. Zero
  // without cam_from_world_rotation.
  Eigen::Matrix3d rotation_covariance = Eigen::Matrix3d::Zero();
  // World down (-z) in the camera frame, when the log has roll and pitch:
  // it needs no yaw.
  std::optional<Eigen::Vector3d> gravity_in_cam;
};

// File names for messages; the records' line numbers refer to them.
struct NavigationSources {
  std::string nav = "nav.csv";
  std::string image_times = "image_times.csv";
};

// One prior per image, in the order of the images:
//  - Without `image_times` the images are the rows of `nav`, matched by
//    name (the log must have an image_name column), each at its row's time.
//  - With `image_times`, at the times given there.
// An image's navigation time is its time + options.time_offset_s. Within
// each dive the rows are a time series (strictly increasing, as
// ReadNavigationCsv checks); an image gets the row at exactly its time, or
// the position interpolated linearly and the attitude slerped between the
// rows around it, and the sigmas interpolated linearly. Beyond the first or
// last row of a dive the end segment is extrapolated, by one sampling
// interval (that segment's) at most; extrapolated priors keep the end row's
// sigmas. An image's dive is the one image_times gives, or the dive whose
// time span, widened by those intervals, holds the time.
// With `rig`, each image belongs to the rig camera whose image_prefix starts
// its name, and world_from_cam = world_from_vehicle * vehicle_from_cam *
// inverse(cam_from_rig), the rig frame being the reference camera, mounted
// as `options` says. Throws uw::Error naming the file, line and image for
// an image outside every dive's span, in no dive or several, of a dive with
// a single row at another time, or of no rig camera.
std::vector<CameraPrior> CameraPriorsFromNavigation(
    const std::vector<NavRecord>& nav,
    const std::vector<ImageTime>* image_times,
    const NavToCameraOptions& options, const RigConfig* rig = nullptr,
    const NavigationSources& sources = {});

// The clock check CameraPriorsFromNavigation makes first, for callers that
// use image times otherwise (model_aligner --associate closest_point): when
// more than half of the images (and at least 2), at their time +
// options.time_offset_s, lie outside every dive's span (their own dive's,
// when image_times gives it), throws uw::Error naming both spans and the
// --time_offset that puts the median of those images at the navigation's
// median time (a camera clock never set is days off).
void CheckImageClock(const std::vector<NavRecord>& nav,
                     const std::vector<ImageTime>& image_times,
                     const NavToCameraOptions& options,
                     const NavigationSources& sources = {});

// Times of the images of a rig whose cameras fire with the fixed delays of
// rig.json, when the log (with image names) samples the reference camera:
// an image named <prefix of camera k><rest> was taken time_offset_s of
// camera k after the row <reference prefix><rest> of `nav`, in that row's
// dive (and `line` is the row's line). Names of no rig camera, or with no
// such row, are left out.
std::vector<ImageTime> RigImageTimes(const std::vector<NavRecord>& nav,
                                     const RigConfig& rig,
                                     const std::vector<std::string>& names);

}  // namespace uw
