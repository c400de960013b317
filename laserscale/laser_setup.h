// Laser scaler geometry as a calibration gives it and lasers.json stores it
// (docs/formats.md): per laser an origin on the camera plane Π (z = 0 of the
// camera frame) and a unit direction, both with covariances, and a colour;
// several set-ups per file, each valid for some dives.
//
// Frame: COLMAP's camera frame (x right, y down, z forward), metres. A laser
// point is origin_in_cam + t * direction_in_cam, t >= 0 metres along the
// beam. The direction's covariance is that of the unit vector: rank 2, its
// null direction along the beam (an isotropic angular sigma s radians is
// s^2 (I - d d^T)).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json_fwd.hpp>

namespace uw {

struct Laser {
  std::string name;
  Eigen::Vector3d origin_in_cam = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction_in_cam = Eigen::Vector3d::UnitZ();
  Eigen::Matrix3d origin_cov = Eigen::Matrix3d::Zero();     // m^2
  Eigen::Matrix3d direction_cov = Eigen::Matrix3d::Zero();  // unitless
  Eigen::Vector3d colour{1.0, 0.0, 0.0};  // linear RGB, each in [0, 1]
};

struct LaserSetup {
  std::string name;
  std::vector<int> dives;  // dives it is valid for; empty: all
  std::vector<Laser> lasers;

  // Throws uw::Error naming the set-up, laser and field: names unique and
  // non-empty, origin on Π (|z| <= 1e-9 m), direction unit (to 1e-9) and
  // forward (z > 0), covariances finite, symmetric and positive
  // semi-definite, colour in [0, 1] and not black.
  void Check() const;
};

// The isotropic angular covariance s^2 (I - d d^T) of a unit direction d.
Eigen::Matrix3d IsotropicDirectionCovariance(const Eigen::Vector3d& direction,
                                             double sigma_rad);

// One laser as in lasers.json's "lasers" arrays; reading needs name,
// origin_in_cam and direction_in_cam (covariances default to zero, colour to
// red) and rejects unknown keys, naming `where`. Geometry is checked by
// LaserSetup::Check.
nlohmann::json LaserJson(const Laser& laser);
Laser LaserFromJson(const nlohmann::json& json, const std::string& where);

// lasers.json: {"format": "uwmetric-lasers", "version": 1, "setups": [...]}.
std::string LasersJsonText(const std::vector<LaserSetup>& setups);
// Reads and checks lasers.json; errors name the file and the offending key.
std::vector<LaserSetup> ReadLasersJson(const std::filesystem::path& path);
std::vector<LaserSetup> ParseLasersJson(const std::string& text,
                                        const std::string& where);

}  // namespace uw
