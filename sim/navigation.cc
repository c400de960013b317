#include "sim/navigation.h"

#include <cmath>
#include <map>
#include <random>

#include <fmt/format.h>

#include "common/util/error.h"
#include "common/util/json_fields.h"

namespace uw::sim {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

void CheckNonNegative(double value, const char* name) {
  if (!(std::isfinite(value) && value >= 0.0)) {
    throw ErrorAt("navigation option ", name, " = ", value,
                  " must be finite and >= 0");
  }
}

const std::vector<std::pair<const char*, double NavigationOptions::*>>&
Fields() {
  static const std::vector<std::pair<const char*, double NavigationOptions::*>>
      fields = {
          {"site_depth_m", &NavigationOptions::site_depth_m},
          {"usbl_sigma_fraction_of_depth",
           &NavigationOptions::usbl_sigma_fraction_of_depth},
          {"dive_bias_fraction_of_depth",
           &NavigationOptions::dive_bias_fraction_of_depth},
          {"drift_fraction_of_speed",
           &NavigationOptions::drift_fraction_of_speed},
          {"drift_correlation_time_s",
           &NavigationOptions::drift_correlation_time_s},
          {"depth_sigma_m", &NavigationOptions::depth_sigma_m},
          {"roll_pitch_sigma_deg", &NavigationOptions::roll_pitch_sigma_deg},
          {"yaw_sigma_deg", &NavigationOptions::yaw_sigma_deg},
      };
  return fields;
}

}  // namespace

void NavigationOptions::Check() const {
  for (const auto& [name, field] : Fields())
    CheckNonNegative(this->*field, name);
  if (drift_correlation_time_s <= 0.0) {
    throw ErrorAt("navigation option drift_correlation_time_s must be > 0");
  }
  for (size_t k = 0; k < dive_biases_m.size(); ++k) {
    if (!dive_biases_m[k].allFinite()) {
      throw ErrorAt("navigation option dive_biases_m[", k, "] must be finite");
    }
  }
}

void NavigationOptions::CheckNumDives(int num_dives) const {
  if (!dive_biases_m.empty() &&
      dive_biases_m.size() != static_cast<size_t>(num_dives)) {
    throw ErrorAt("navigation option dive_biases_m has ", dive_biases_m.size(),
                  " entries; the survey has ", num_dives,
                  " dive(s) and needs one per dive");
  }
}

void to_json(nlohmann::json& json, const NavigationOptions& options) {
  json = nlohmann::json::object();
  for (const auto& [name, field] : Fields()) json[name] = options.*field;
  // Written only when set, so that sim.json without it is unchanged.
  if (!options.dive_biases_m.empty()) {
    json["dive_biases_m"] = ToJson(options.dive_biases_m);
  }
}

void from_json(const nlohmann::json& json, NavigationOptions& options) {
  JsonFields fields(json, "navigation");
  for (const auto& [name, field] : Fields())
    fields.Read(name, &(options.*field));
  fields.Read("dive_biases_m", &options.dive_biases_m);
  fields.RejectUnknown();
}

std::vector<NavigationRecord> TrueNavigation(
    const std::vector<SurveyStation>& stations) {
  std::vector<NavigationRecord> records;
  for (const SurveyStation& station : stations) {
    NavigationRecord record;
    record.image_name = station.image_name;
    record.time_s = station.time_s;
    record.dive = station.dive;
    record.position = station.vehicle_position;
    record.rpy = station.vehicle_rpy;
    records.push_back(record);
  }
  return records;
}

std::vector<NavigationRecord> NoisyNavigation(
    const std::vector<SurveyStation>& stations,
    const NavigationOptions& options, uint64_t seed,
    std::vector<Eigen::Vector3d>* dive_biases) {
  options.Check();
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal01(0.0, 1.0);
  const auto gaussian3 = [&] {
    return Eigen::Vector3d(normal01(rng), normal01(rng), normal01(rng));
  };
  const auto depth_of = [&](const Eigen::Vector3d& position) {
    return std::max(0.0, options.site_depth_m - position.z());
  };

  // Biases per dive, horizontal only: the depth sensor is absolute.
  std::map<int, Eigen::Vector3d> biases;
  for (const SurveyStation& station : stations) {
    if (biases.count(station.dive) == 0) {
      const double sigma = options.dive_bias_fraction_of_depth *
                           depth_of(station.vehicle_position);
      Eigen::Vector3d bias = sigma * gaussian3();
      bias.z() = 0.0;
      if (!options.dive_biases_m.empty()) {
        if (station.dive < 1 ||
            station.dive > static_cast<int>(options.dive_biases_m.size())) {
          throw ErrorAt("navigation option dive_biases_m has ",
                        options.dive_biases_m.size(), " entries; image ",
                        station.image_name, " is of dive ", station.dive);
        }
        bias = options.dive_biases_m[station.dive - 1];
      }
      biases[station.dive] = bias;
    }
  }
  if (dive_biases != nullptr) {
    dive_biases->clear();
    for (const auto& [dive, bias] : biases) dive_biases->push_back(bias);
  }

  std::vector<NavigationRecord> records = TrueNavigation(stations);
  Eigen::Vector3d drift = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_error = Eigen::Vector3d::Zero();
  int current_dive = stations.empty() ? 0 : stations[0].dive;
  for (size_t i = 0; i < records.size(); ++i) {
    NavigationRecord& record = records[i];
    if (record.dive != current_dive) {
      drift.setZero();
      velocity_error.setZero();
      current_dive = record.dive;
    }
    if (i > 0 && records[i - 1].dive == record.dive) {
      const double dt = record.time_s - records[i - 1].time_s;
      const double speed = dt > 0.0 ? (stations[i].vehicle_position -
                                       stations[i - 1].vehicle_position)
                                              .norm() /
                                          dt
                                    : 0.0;
      // Exact discretisation of a Gauss-Markov process keeps the drift's
      // statistics independent of the image rate.
      const double decay = std::exp(-dt / options.drift_correlation_time_s);
      const double sigma = options.drift_fraction_of_speed * speed;
      velocity_error = decay * velocity_error +
                       sigma * std::sqrt(1.0 - decay * decay) * gaussian3();
      velocity_error.z() = 0.0;
      drift += velocity_error * dt;
    }
    const double usbl_sigma =
        options.usbl_sigma_fraction_of_depth * depth_of(record.position);
    Eigen::Vector3d noise = gaussian3();
    noise.x() *= usbl_sigma;
    noise.y() *= usbl_sigma;
    noise.z() *= options.depth_sigma_m;
    record.position += biases.at(record.dive) + drift + noise;
    const Eigen::Vector3d rpy_sigma =
        kDegToRad * Eigen::Vector3d(options.roll_pitch_sigma_deg,
                                    options.roll_pitch_sigma_deg,
                                    options.yaw_sigma_deg);
    record.rpy += rpy_sigma.cwiseProduct(gaussian3());
    record.position_sigma =
        Eigen::Vector3d(usbl_sigma, usbl_sigma, options.depth_sigma_m);
    record.rpy_sigma = rpy_sigma;
  }
  return records;
}

std::string NavigationCsv(const std::vector<NavigationRecord>& records,
                          double site_depth_m, const std::string& time_units) {
  std::string csv = fmt::format(
      "# uwsim navigation: vehicle position x,y,z in m in the site's local "
      "East-North-Up frame whose origin is {0:.17g} m deep (depth = {0:.17g} "
      "- z); roll,pitch,yaw in deg with world_from_vehicle = "
      "Rz(yaw)*Ry(pitch)*Rx(roll), vehicle x forward, y left, z up; time in "
      "{1}; std_* are 1-sigma\n"
      "image_name,time,dive,x,y,z,roll,pitch,yaw,std_x,std_y,std_z,"
      "std_roll,std_pitch,std_yaw\n",
      site_depth_m, time_units);
  const double to_deg = 180.0 / M_PI;
  for (const NavigationRecord& record : records) {
    csv += fmt::format("{},{:.17g},{}", record.image_name, record.time_s,
                       record.dive);
    for (int k = 0; k < 3; ++k)
      csv += fmt::format(",{:.17g}", record.position(k));
    for (int k = 0; k < 3; ++k) {
      csv += fmt::format(",{:.17g}", record.rpy(k) * to_deg);
    }
    for (int k = 0; k < 3; ++k) {
      csv += fmt::format(",{:.17g}", record.position_sigma(k));
    }
    for (int k = 0; k < 3; ++k) {
      csv += fmt::format(",{:.17g}", record.rpy_sigma(k) * to_deg);
    }
    csv += "\n";
  }
  return csv;
}

}  // namespace uw::sim
