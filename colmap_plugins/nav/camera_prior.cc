#include "colmap_plugins/nav/camera_prior.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

#include <fmt/format.h>

#include "colmap_plugins/nav/attitude.h"
#include "common/util/error.h"
#include "common/util/median.h"
#include "common/util/time_text.h"

namespace uw {
namespace {

// Times within this fraction of a sampling interval of a span's end count
// as inside it: image times written with 17 digits can land a rounding
// error beyond an extrapolation limit they were computed to meet.
constexpr double kRelativeTimeSlack = 1e-9;

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d skew;
  skew << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return skew;
}

// The vehicle at one time.
struct VehicleState {
  Eigen::Vector3d position;
  Eigen::Quaterniond world_from_vehicle;
  Eigen::Vector3d rpy;  // of world_from_vehicle
  Eigen::Vector3d position_sigma;
  Eigen::Vector3d rpy_sigma;
  NavSampling sampling = NavSampling::kExact;
  // What the log has (NavRecord); the rest of rpy is 0 and means nothing.
  bool has_roll_pitch = true;
  bool has_yaw = true;
};

VehicleState StateOfRow(const NavRecord& row) {
  return {row.position,
          Eigen::Quaterniond(WorldFromVehicleRotation(row.rpy_rad)),
          row.rpy_rad,
          row.position_sigma,
          row.rpy_sigma_rad,
          NavSampling::kExact,
          row.has_roll_pitch,
          row.has_yaw};
}

// Linear in position, slerp in attitude along the segment a -> b at
// `fraction` (outside [0, 1]: extrapolated along the same motion). Sigmas
// are interpolated, never extrapolated.
VehicleState Interpolate(const NavRecord& a, const NavRecord& b,
                         double fraction) {
  VehicleState state;
  state.position = a.position + fraction * (b.position - a.position);
  const Eigen::Quaterniond qa(WorldFromVehicleRotation(a.rpy_rad));
  const Eigen::Quaterniond qb(WorldFromVehicleRotation(b.rpy_rad));
  // qa (qa^-1 qb)^fraction along the shorter arc; Eigen's AngleAxis of a
  // quaternion has its angle in [0, pi].
  const Eigen::AngleAxisd step(qa.conjugate() * qb);
  state.world_from_vehicle = qa * Eigen::Quaterniond(Eigen::AngleAxisd(
                                      fraction * step.angle(), step.axis()));
  state.rpy =
      RollPitchYawFromRotation(state.world_from_vehicle.toRotationMatrix());
  const double clamped = std::clamp(fraction, 0.0, 1.0);
  state.position_sigma =
      a.position_sigma + clamped * (b.position_sigma - a.position_sigma);
  state.rpy_sigma =
      a.rpy_sigma_rad + clamped * (b.rpy_sigma_rad - a.rpy_sigma_rad);
  state.sampling = fraction >= 0.0 && fraction <= 1.0
                       ? NavSampling::kInterpolated
                       : NavSampling::kExtrapolated;
  state.has_roll_pitch = a.has_roll_pitch && b.has_roll_pitch;
  state.has_yaw = a.has_yaw && b.has_yaw;
  return state;
}

// The rows of one dive, in time order, and how far beyond its ends it may
// be extrapolated.
struct Dive {
  std::vector<const NavRecord*> rows;

  double Start() const { return rows.front()->time_s; }
  double End() const { return rows.back()->time_s; }
  double FirstInterval() const {
    return rows.size() > 1 ? rows[1]->time_s - rows[0]->time_s : 0.0;
  }
  double LastInterval() const {
    return rows.size() > 1 ? rows.back()->time_s - rows[rows.size() - 2]->time_s
                           : 0.0;
  }
  bool Covers(double time) const {
    return time >= Start() - FirstInterval() * (1.0 + kRelativeTimeSlack) &&
           time <= End() + LastInterval() * (1.0 + kRelativeTimeSlack);
  }
  std::string Span(const std::string& nav_name) const {
    return fmt::format("{} to {} s, {} lines {} to {}", TimeText(Start()),
                       TimeText(End()), nav_name, rows.front()->line,
                       rows.back()->line);
  }
};

// One image to place: its name, navigation time and dive (0: unknown).
struct ImageToPlace {
  std::string name;
  double time_s = 0.0;
  int dive = 0;
  std::string where;  // "file:line"
};

class Navigation {
 public:
  Navigation(const std::vector<NavRecord>& nav, const std::string& nav_name)
      : nav_name_(nav_name) {
    for (const NavRecord& row : nav) dives_[row.dive].rows.push_back(&row);
    // ReadNavigationCsv checks this; records built otherwise must obey too.
    for (const auto& [number, dive] : dives_) {
      for (size_t i = 1; i < dive.rows.size(); ++i) {
        if (!(dive.rows[i]->time_s > dive.rows[i - 1]->time_s)) {
          throw ErrorAt(nav_name_, ":", dive.rows[i]->line, ": time ",
                        TimeText(dive.rows[i]->time_s),
                        " s is not after the previous row of dive ", number,
                        " (line ", dive.rows[i - 1]->line, ")");
        }
      }
    }
  }

  // Most of the images outside the navigation is one clock, not stray
  // images: the error says by how much, before any one image is refused.
  void CheckClock(const std::vector<ImageToPlace>& images, double time_offset_s,
                  const std::string& images_file) const {
    std::vector<double> outside;
    std::vector<double> image_times;
    for (const ImageToPlace& image : images) {
      image_times.push_back(image.time_s);
      const auto dive = dives_.find(image.dive);
      const bool covered =
          dive != dives_.end()
              ? dive->second.Covers(image.time_s)
              : std::any_of(dives_.begin(), dives_.end(), [&](const auto& d) {
                  return d.second.Covers(image.time_s);
                });
      if (!covered) outside.push_back(image.time_s);
    }
    if (outside.size() < 2 || 2 * outside.size() <= images.size()) return;
    std::vector<double> nav_times;
    for (const auto& [number, dive] : dives_) {
      for (const NavRecord* row : dive.rows) nav_times.push_back(row->time_s);
    }
    const double shift = Median(nav_times) - Median(outside);
    const auto [first, last] =
        std::minmax_element(image_times.begin(), image_times.end());
    const auto [nav_first, nav_last] =
        std::minmax_element(nav_times.begin(), nav_times.end());
    throw ErrorAt(
        images_file, ": ", outside.size(), " of its ", images.size(),
        " images lie outside the navigation (the images from ",
        TimeText(*first), " to ", TimeText(*last),
        " s on the navigation's clock, with --time_offset ",
        SecondsText(time_offset_s), "; ", nav_name_, " from ",
        TimeText(*nav_first), " to ", TimeText(*nav_last),
        " s). Is the camera clock off by about ", DurationText(shift),
        "? --time_offset ",
        SecondsText(std::round((time_offset_s + shift) * 1000.0) / 1000.0),
        " puts the median of those ", outside.size(),
        " at the navigation's median time");
  }

  int DiveOf(const ImageToPlace& image) const {
    if (image.dive != 0) {
      if (dives_.count(image.dive) == 0) {
        throw ErrorAt(image.where, ": image '", image.name, "' is of dive ",
                      image.dive, ", which ", nav_name_, " has no rows for");
      }
      return image.dive;
    }
    std::vector<int> covering;
    for (const auto& [number, dive] : dives_) {
      if (dive.Covers(image.time_s)) covering.push_back(number);
    }
    if (covering.size() == 1) return covering[0];
    std::string spans;
    for (const auto& [number, dive] : dives_) {
      spans += fmt::format("; dive {}: {}", number, dive.Span(nav_name_));
    }
    if (covering.empty()) {
      throw ErrorAt(image.where, ": image '", image.name,
                    "' at navigation time ", TimeText(image.time_s),
                    " s lies outside the navigation of every dive, even "
                    "allowing one sampling interval beyond each end",
                    spans);
    }
    throw ErrorAt(image.where, ": image '", image.name, "' at navigation time ",
                  TimeText(image.time_s),
                  " s lies in the navigation of several dives", spans,
                  "; give image_times.csv a dive column");
  }

  // The vehicle when `image` was taken in dive `number` (from DiveOf).
  VehicleState At(const ImageToPlace& image, int number) const {
    const Dive& dive = dives_.at(number);
    const double time = image.time_s;
    const auto& rows = dive.rows;
    const auto after = std::lower_bound(
        rows.begin(), rows.end(), time,
        [](const NavRecord* row, double t) { return row->time_s < t; });
    if (after != rows.end() && (*after)->time_s == time) {
      return StateOfRow(**after);
    }
    if (rows.size() == 1 || !dive.Covers(time)) {
      throw ErrorAt(image.where, ": image '", image.name,
                    "' at navigation time ", TimeText(image.time_s),
                    " s lies outside the navigation of dive ", number, " (",
                    dive.Span(nav_name_),
                    rows.size() == 1
                        ? "): a single row gives a prior only at its own time"
                        : "): extrapolation reaches one sampling interval "
                          "beyond each end at most");
    }
    size_t to = static_cast<size_t>(after - rows.begin());
    to = std::clamp<size_t>(to, 1, rows.size() - 1);
    const NavRecord& a = *rows[to - 1];
    const NavRecord& b = *rows[to];
    return Interpolate(a, b, (time - a.time_s) / (b.time_s - a.time_s));
  }

 private:
  std::string nav_name_;
  std::map<int, Dive> dives_;
};

// The images of image_times.csv at their navigation times.
std::vector<ImageToPlace> ImagesAtTheirTimes(
    const std::vector<ImageTime>& image_times,
    const NavToCameraOptions& options, const NavigationSources& sources) {
  std::vector<ImageToPlace> images;
  for (const ImageTime& image : image_times) {
    images.push_back({image.image_name, image.time_s + options.time_offset_s,
                      image.dive,
                      sources.image_times + ":" + std::to_string(image.line)});
  }
  return images;
}

Rigid3d Compose(const Rigid3d& c_from_b, const Rigid3d& b_from_a) {
  Rigid3d c_from_a;
  c_from_a.rotation = c_from_b.rotation * b_from_a.rotation;
  c_from_a.translation = c_from_b * b_from_a.translation;
  return c_from_a;
}

CameraPrior PriorOf(const ImageToPlace& image, int dive,
                    const VehicleState& vehicle,
                    const Rigid3d& vehicle_from_cam,
                    double unlogged_roll_pitch_sigma_rad) {
  CameraPrior prior;
  prior.image_name = image.name;
  prior.dive = dive;
  prior.time_s = image.time_s;
  prior.sampling = vehicle.sampling;
  const Eigen::Matrix3d position_covariance =
      vehicle.position_sigma.cwiseAbs2().asDiagonal();
  if (vehicle.has_roll_pitch) {
    // World down in the camera: the same for every yaw, so rpy's yaw (0
    // when not logged) does not matter.
    prior.gravity_in_cam =
        (vehicle.world_from_vehicle * vehicle_from_cam.rotation.normalized())
            .conjugate() *
        -Eigen::Vector3d::UnitZ();
  }
  Eigen::Vector3d rpy_sigma = vehicle.rpy_sigma;
  if (!vehicle.has_roll_pitch) {
    rpy_sigma.head<2>().setConstant(unlogged_roll_pitch_sigma_rad);
  }
  if (!vehicle.has_yaw) {
    // The lever arm turns with the unknown yaw: only its vertical part is
    // known, its horizontal part h lies anywhere on a circle (variance
    // |h|²/2 along each horizontal axis; a uniform circle, not a Gaussian).
    // Roll and pitch tilt it on top, by their sigmas (logged, or
    // unlogged_roll_pitch_sigma): that share, taken at yaw 0, is averaged
    // over the yaw it could have (its horizontal trace split evenly).
    const Eigen::Vector3d lever_arm_levelled =
        vehicle.world_from_vehicle * vehicle_from_cam.translation;
    prior.position =
        vehicle.position + lever_arm_levelled.z() * Eigen::Vector3d::UnitZ();
    const Eigen::Matrix3d lever_skew = Skew(lever_arm_levelled);
    const Eigen::Matrix3d tilt =
        lever_skew *
        WorldRotationCovariance(
            vehicle.rpy, Eigen::Vector3d(rpy_sigma.x(), rpy_sigma.y(), 0.0)) *
        lever_skew.transpose();
    const double horizontal = 0.5 * lever_arm_levelled.head<2>().squaredNorm() +
                              0.5 * (tilt(0, 0) + tilt(1, 1));
    prior.position_covariance =
        position_covariance +
        Eigen::Vector3d(horizontal, horizontal, tilt(2, 2))
            .asDiagonal()
            .toDenseMatrix();
    return prior;
  }
  const Eigen::Matrix3d world_from_vehicle =
      vehicle.world_from_vehicle.toRotationMatrix();
  const Eigen::Vector3d lever_arm_in_world =
      world_from_vehicle * vehicle_from_cam.translation;
  prior.position = vehicle.position + lever_arm_in_world;
  const Eigen::Matrix3d rotation_covariance =
      WorldRotationCovariance(vehicle.rpy, rpy_sigma);
  const Eigen::Matrix3d lever_skew = Skew(lever_arm_in_world);
  prior.position_covariance = position_covariance + lever_skew *
                                                        rotation_covariance *
                                                        lever_skew.transpose();
  if (vehicle.has_roll_pitch) {
    prior.cam_from_world_rotation =
        (vehicle.world_from_vehicle * vehicle_from_cam.rotation.normalized())
            .conjugate()
            .normalized();
    prior.rotation_covariance = rotation_covariance;
  }
  return prior;
}

}  // namespace

std::vector<CameraPrior> CameraPriorsFromNavigation(
    const std::vector<NavRecord>& nav,
    const std::vector<ImageTime>* image_times,
    const NavToCameraOptions& options, const RigConfig* rig,
    const NavigationSources& sources) {
  options.Check();
  if (rig != nullptr) rig->Check();
  if (nav.empty()) throw ErrorAt(sources.nav, ": no navigation rows");

  std::vector<ImageToPlace> images;
  if (image_times != nullptr) {
    images = ImagesAtTheirTimes(*image_times, options, sources);
  } else {
    for (const NavRecord& row : nav) {
      const std::string where = sources.nav + ":" + std::to_string(row.line);
      if (row.image_name.empty()) {
        throw ErrorAt(where,
                      ": the navigation has no image names; give the "
                      "images' times (image_times.csv)");
      }
      images.push_back({row.image_name, row.time_s + options.time_offset_s,
                        row.dive, where});
    }
  }

  const Navigation navigation(nav, sources.nav);
  navigation.CheckClock(
      images, options.time_offset_s,
      image_times != nullptr ? sources.image_times : sources.nav);
  const Rigid3d vehicle_from_reference = VehicleFromCam(options);
  std::vector<CameraPrior> priors;
  priors.reserve(images.size());
  for (const ImageToPlace& image : images) {
    Rigid3d vehicle_from_cam = vehicle_from_reference;
    if (rig != nullptr) {
      const RigCameraConfig* camera = rig->CameraOfImage(image.name);
      if (camera == nullptr) {
        std::string prefixes;
        for (const RigCameraConfig& rig_camera : rig->cameras) {
          prefixes +=
              (prefixes.empty() ? "'" : ", '") + rig_camera.image_prefix + "'";
        }
        throw ErrorAt(image.where, ": image '", image.name,
                      "' belongs to no camera of the rig (image prefixes ",
                      prefixes, ")");
      }
      vehicle_from_cam =
          Compose(vehicle_from_reference, camera->cam_from_rig.Inverse());
    }
    const int dive = navigation.DiveOf(image);
    priors.push_back(
        PriorOf(image, dive, navigation.At(image, dive), vehicle_from_cam,
                options.unlogged_roll_pitch_sigma_deg * M_PI / 180.0));
  }
  return priors;
}

void CheckImageClock(const std::vector<NavRecord>& nav,
                     const std::vector<ImageTime>& image_times,
                     const NavToCameraOptions& options,
                     const NavigationSources& sources) {
  if (nav.empty()) throw ErrorAt(sources.nav, ": no navigation rows");
  Navigation(nav, sources.nav)
      .CheckClock(ImagesAtTheirTimes(image_times, options, sources),
                  options.time_offset_s, sources.image_times);
}

std::vector<ImageTime> RigImageTimes(const std::vector<NavRecord>& nav,
                                     const RigConfig& rig,
                                     const std::vector<std::string>& names) {
  rig.Check();
  std::unordered_map<std::string, const NavRecord*> row_of_name;
  for (const NavRecord& row : nav) row_of_name.emplace(row.image_name, &row);
  const std::string& reference_prefix = rig.cameras.front().image_prefix;
  std::vector<ImageTime> times;
  for (const std::string& name : names) {
    const RigCameraConfig* camera = rig.CameraOfImage(name);
    if (camera == nullptr) continue;
    const auto row = row_of_name.find(reference_prefix +
                                      name.substr(camera->image_prefix.size()));
    if (row == row_of_name.end()) continue;
    times.push_back({name, row->second->time_s + camera->time_offset_s,
                     row->second->dive, row->second->line});
  }
  return times;
}

}  // namespace uw
