#include "laserscale/laser_setup.h"

#include <cmath>
#include <set>

#include <Eigen/Eigenvalues>
#include <nlohmann/json.hpp>

#include "common/util/error.h"
#include "common/util/file.h"
#include "common/util/json_fields.h"

namespace uw {
namespace {

constexpr char kFormat[] = "uwmetric-lasers";
constexpr int kVersion = 1;

void CheckCovariance(const Eigen::Matrix3d& cov, const std::string& where) {
  if (!cov.allFinite()) throw ErrorAt(where, ": not finite");
  const double scale = std::max(cov.cwiseAbs().maxCoeff(), 1e-300);
  if (((cov - cov.transpose()).cwiseAbs().maxCoeff()) > 1e-12 * scale) {
    throw ErrorAt(where, ": not symmetric");
  }
  const double min_eigenvalue =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvalues()(0);
  if (min_eigenvalue < -1e-12 * scale) {
    throw ErrorAt(where, ": not positive semi-definite (eigenvalue ",
                  min_eigenvalue, ")");
  }
}

}  // namespace

void LaserSetup::Check() const {
  if (name.empty()) throw ErrorAt("laser set-up without a name");
  if (lasers.empty()) throw ErrorAt("laser set-up ", name, ": no lasers");
  std::set<std::string> names;
  for (const Laser& laser : lasers) {
    const std::string where = "laser set-up " + name + ", laser " + laser.name;
    if (laser.name.empty()) {
      throw ErrorAt("laser set-up ", name, ": a laser without a name");
    }
    if (!names.insert(laser.name).second) {
      throw ErrorAt(where, ": name used twice");
    }
    if (!laser.origin_in_cam.allFinite() ||
        std::abs(laser.origin_in_cam.z()) > 1e-9) {
      throw ErrorAt(where,
                    ": origin_in_cam must be finite with z = 0 (on "
                    "the camera plane), got ",
                    laser.origin_in_cam.transpose());
    }
    if (!laser.direction_in_cam.allFinite() ||
        std::abs(laser.direction_in_cam.norm() - 1.0) > 1e-9 ||
        laser.direction_in_cam.z() <= 0.0) {
      throw ErrorAt(where,
                    ": direction_in_cam must be a unit vector with z > 0 "
                    "(forward), got ",
                    laser.direction_in_cam.transpose());
    }
    CheckCovariance(laser.origin_cov, where + ": origin_cov");
    CheckCovariance(laser.direction_cov, where + ": direction_cov");
    if (!(laser.colour.minCoeff() >= 0.0 && laser.colour.maxCoeff() <= 1.0)) {
      throw ErrorAt(where, ": colour must be in [0, 1], got ",
                    laser.colour.transpose());
    }
    if (!(laser.colour.maxCoeff() > 0.0)) {
      throw ErrorAt(where, ": colour is black (0, 0, 0): no light to detect");
    }
  }
  for (const int dive : dives) {
    if (dive < 1) throw ErrorAt("laser set-up ", name, ": dive ", dive, " < 1");
  }
}

Eigen::Matrix3d IsotropicDirectionCovariance(const Eigen::Vector3d& direction,
                                             double sigma_rad) {
  const Eigen::Vector3d unit = direction.normalized();
  return sigma_rad * sigma_rad *
         (Eigen::Matrix3d::Identity() - unit * unit.transpose());
}

nlohmann::json LaserJson(const Laser& laser) {
  return {{"name", laser.name},
          {"origin_in_cam", ToJson(laser.origin_in_cam)},
          {"direction_in_cam", ToJson(laser.direction_in_cam)},
          {"origin_cov", ToJson(laser.origin_cov)},
          {"direction_cov", ToJson(laser.direction_cov)},
          {"colour", ToJson(laser.colour)}};
}

Laser LaserFromJson(const nlohmann::json& json, const std::string& where) {
  JsonFields fields(json, where);
  Laser laser;
  fields.Require("name", &laser.name);
  fields.Require("origin_in_cam", &laser.origin_in_cam);
  fields.Require("direction_in_cam", &laser.direction_in_cam);
  fields.Read("origin_cov", &laser.origin_cov);
  fields.Read("direction_cov", &laser.direction_cov);
  fields.Read("colour", &laser.colour);
  fields.RejectUnknown();
  return laser;
}

std::string LasersJsonText(const std::vector<LaserSetup>& setups) {
  nlohmann::json json_setups = nlohmann::json::array();
  for (const LaserSetup& setup : setups) {
    setup.Check();
    nlohmann::json lasers = nlohmann::json::array();
    for (const Laser& laser : setup.lasers) {
      lasers.push_back(LaserJson(laser));
    }
    json_setups.push_back(
        {{"name", setup.name}, {"dives", setup.dives}, {"lasers", lasers}});
  }
  const nlohmann::json json = {
      {"format", kFormat},
      {"version", kVersion},
      {"frame",
       "camera: x right, y down, z forward (COLMAP); metres; origins on the "
       "camera plane z = 0"},
      {"setups", json_setups}};
  return json.dump(2) + "\n";
}

std::vector<LaserSetup> ParseLasersJson(const std::string& text,
                                        const std::string& where) {
  const nlohmann::json json = ParseJsonText(text, where);
  JsonFields file(json, where);
  file.RequireFormat(kFormat, kVersion);
  std::string frame;
  nlohmann::json json_setups;
  file.Read("frame", &frame);
  file.Require("setups", &json_setups);
  file.RejectUnknown();
  if (!json_setups.is_array() || json_setups.empty()) {
    throw ErrorAt(where, ": \"setups\" must be a non-empty array");
  }
  std::vector<LaserSetup> setups;
  std::set<std::string> setup_names;
  for (size_t s = 0; s < json_setups.size(); ++s) {
    const std::string setup_where =
        where + ": setups[" + std::to_string(s) + "]";
    JsonFields fields(json_setups[s], setup_where);
    LaserSetup setup;
    nlohmann::json json_lasers;
    fields.Require("name", &setup.name);
    fields.Read("dives", &setup.dives);
    fields.Require("lasers", &json_lasers);
    fields.RejectUnknown();
    if (!json_lasers.is_array()) {
      throw ErrorAt(setup_where, ".lasers: expected an array");
    }
    for (size_t l = 0; l < json_lasers.size(); ++l) {
      setup.lasers.push_back(LaserFromJson(
          json_lasers[l], setup_where + ".lasers[" + std::to_string(l) + "]"));
    }
    try {
      setup.Check();
    } catch (const Error& error) {
      throw ErrorAt(where, ": ", error.what());
    }
    if (!setup_names.insert(setup.name).second) {
      throw ErrorAt(where, ": set-up name \"", setup.name, "\" used twice");
    }
    setups.push_back(std::move(setup));
  }
  return setups;
}

std::vector<LaserSetup> ReadLasersJson(const std::filesystem::path& path) {
  return ParseLasersJson(ReadFileToString(path), path.string());
}

}  // namespace uw
