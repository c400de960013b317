// nav.csv, the navigation log (docs/formats.md): per row the vehicle's
// position and attitude at a time, with their standard deviations.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace uw {

struct NavRecord {
  // Empty when the log has no image_name column (a log sampled at its own
  // times; images then get their times from image_times.csv).
  std::string image_name;
  double time_s = 0.0;
  int dive = 1;  // 1 when the log has no dive column
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // vehicle, world, m
  Eigen::Vector3d rpy_rad = Eigen::Vector3d::Zero();   // attitude.h
  // 0: not stated (a log without std_x, std_y, std_z).
  Eigen::Vector3d position_sigma = Eigen::Vector3d::Zero();  // m, world axes
  Eigen::Vector3d rpy_sigma_rad = Eigen::Vector3d::Zero();
  // Whether the log has roll and pitch, and yaw (or heading): most USBL
  // exports have neither. What was not logged reads 0 above and means
  // nothing: camera_prior.h says what a prior then holds.
  bool has_roll_pitch = true;
  bool has_yaw = true;
  int line = 0;  // 1-based line in the file, for messages
};

// Reads nav.csv strictly: the header names the columns time, x, y, z and
// optionally image_name, dive, roll and pitch (together), yaw or heading
// (clockwise from north: yaw = 90 - heading), and the sigmas std_x, std_y,
// std_z (together), std_roll, std_pitch (with roll, pitch) and std_yaw or
// std_heading (with yaw or heading), in any order; every value is a finite
// number, dives are integers >= 1, sigmas >= 0, image names are non-empty
// and unique, and within a dive the rows come in strictly increasing time.
// Sigmas not given read 0. Throws uw::Error naming the file and line.
std::vector<NavRecord> ReadNavigationCsv(const std::filesystem::path& path);

}  // namespace uw
