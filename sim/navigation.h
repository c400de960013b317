// Synthetic vehicle navigation with the errors of a real ROV/AUV log:
// USBL-like position noise proportional to depth, a constant bias per dive,
// a smooth DVL/INS-like drift, an accurate depth sensor and small attitude
// noise. Written as nav.csv (docs/formats.md).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sim/survey.h"

namespace uw::sim {

struct NavigationOptions {
  // Depth of the world origin (z = 0) below the sea surface, m. A vehicle at
  // world height z is at depth site_depth_m − z.
  double site_depth_m = 100.0;
  // Horizontal white noise: σ = fraction × vehicle depth (USBL ~1 %).
  double usbl_sigma_fraction_of_depth = 0.01;
  // Constant per-dive horizontal bias drawn with σ = fraction × depth.
  double dive_bias_fraction_of_depth = 0.01;
  // Explicit per-dive biases (world frame, m), dive 1 first: when not empty
  // they replace the random draw (which is still made, so that the other
  // errors stay those of the same seed). One entry per dive of the survey
  // (SimConfig::Check); z is usually 0, as the depth sensor is absolute.
  std::vector<Eigen::Vector3d> dive_biases_m;
  // Smooth drift: a first-order Gauss-Markov velocity error with σ =
  // fraction × speed and correlation time tau, integrated over time.
  double drift_fraction_of_speed = 0.01;
  double drift_correlation_time_s = 60.0;
  double depth_sigma_m = 0.02;
  double roll_pitch_sigma_deg = 0.05;
  double yaw_sigma_deg = 0.2;

  void Check() const;
  // Throws uw::Error unless dive_biases_m is empty or has num_dives entries.
  void CheckNumDives(int num_dives) const;
};
void to_json(nlohmann::json& json, const NavigationOptions& options);
void from_json(const nlohmann::json& json, NavigationOptions& options);

// One navigation record: the vehicle's position (world frame, m) and
// attitude (roll, pitch, yaw, rad) at the time an image was taken, with the
// standard deviations a navigation system would report (white noise only).
struct NavigationRecord {
  std::string image_name;
  double time_s = 0.0;
  int dive = 1;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d rpy = Eigen::Vector3d::Zero();
  Eigen::Vector3d position_sigma = Eigen::Vector3d::Zero();
  Eigen::Vector3d rpy_sigma = Eigen::Vector3d::Zero();
};

// The true navigation of the survey (no error; sigmas zero).
std::vector<NavigationRecord> TrueNavigation(
    const std::vector<SurveyStation>& stations);

// Navigation with errors; deterministic for a seed. `dive_biases` receives
// the bias applied to each dive (index dive − 1), for the ground truth.
// Throws uw::Error when options.dive_biases_m is given without an entry for
// every dive of the stations.
std::vector<NavigationRecord> NoisyNavigation(
    const std::vector<SurveyStation>& stations,
    const NavigationOptions& options, uint64_t seed,
    std::vector<Eigen::Vector3d>* dive_biases);

// nav.csv text: a comment header stating frame and units, then
// image_name,time,dive,x,y,z,roll,pitch,yaw,std_x,std_y,std_z,std_roll,
// std_pitch,std_yaw (angles in degrees). Times are written as the records
// hold them; `time_units` says what they are (LogTimeUnits).
std::string NavigationCsv(
    const std::vector<NavigationRecord>& records, double site_depth_m,
    const std::string& time_units = "seconds since the survey's start");

}  // namespace uw::sim
