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
  Eigen::Vector3d position_sigma = Eigen::Vector3d::Zero();  // m, world axes
  Eigen::Vector3d rpy_sigma_rad = Eigen::Vector3d::Zero();
  int line = 0;  // 1-based line in the file, for messages
};

// Reads nav.csv strictly: the header names the columns image_name, time,
// dive, x, y, z, roll, pitch, yaw, std_x, std_y, std_z, std_roll,
// std_pitch, std_yaw (any order; image_name and dive may be left out);
// every value is a finite number, dives are integers >= 1, sigmas >= 0,
// image names are non-empty and unique, and within a dive the rows come in
// strictly increasing time. Throws uw::Error naming the file and line.
std::vector<NavRecord> ReadNavigationCsv(const std::filesystem::path& path);

}  // namespace uw
