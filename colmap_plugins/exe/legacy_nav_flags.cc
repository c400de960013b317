#include "colmap_plugins/exe/legacy_nav_flags.h"

#include <charconv>
#include <cmath>
#include <sstream>

#include "common/util/error.h"

namespace uw {

Eigen::Vector3d ParseVector3(const std::string& text, const std::string& flag) {
  Eigen::Vector3d value;
  size_t start = 0;
  for (int k = 0; k < 3; ++k) {
    const size_t comma = k < 2 ? text.find(',', start) : text.size();
    const char* first = text.data() + start;
    const char* last = text.data() + std::min(comma, text.size());
    const auto [end, error] = std::from_chars(first, last, value(k));
    if (comma == std::string::npos || error != std::errc() || end != last ||
        !std::isfinite(value(k))) {
      throw ErrorAt("--", flag, ": expected three numbers x,y,z, got '", text,
                    "'");
    }
    start = comma + 1;
  }
  return value;
}

void NavFlags::Add(CLI::App& app, bool nav_required,
                   const std::string& rig_flag) {
  CLI::Option* nav = app.add_option(
      "--nav", nav_path,
      "Navigation log (nav.csv: vehicle position x,y,z in m, roll,pitch,yaw "
      "in deg, their sigmas; docs/formats.md)");
  if (nav_required) nav->required();
  app.add_option("--image_times", image_times_path,
                 "image_name,time of every image (image_times.csv); the "
                 "log is then a time series interpolated at those times");
  app.add_option(rig_flag, rig_config_path,
                 "Camera rig (rig.json): each image gets the pose of the rig "
                 "camera whose image_prefix starts its name");
  app.add_option("--mount", mount,
                 "How the (reference) camera looks: down, starboard, port, "
                 "forward")
      ->default_val("down");
  app.add_option("--lever_arm", lever_arm,
                 "Camera centre in the vehicle frame (x forward, y left, z "
                 "up), m: x,y,z")
      ->default_val("0,0,0");
  app.add_option("--boresight", boresight,
                 "Small rotation after the mount, roll,pitch,yaw in deg")
      ->default_val("0,0,0");
  app.add_option("--time_offset", time_offset,
                 "Seconds added to every image time to get the navigation "
                 "time at which it was taken")
      ->default_val(0.0);
}

PosePriorImportOptions NavFlags::ToOptions() const {
  PosePriorImportOptions options;
  options.nav_path = nav_path;
  options.image_times_path = image_times_path;
  options.rig_config_path = rig_config_path;
  options.nav_to_camera.mount = CameraMountFromName(mount);
  options.nav_to_camera.lever_arm_m = ParseVector3(lever_arm, "lever_arm");
  options.nav_to_camera.boresight_deg = ParseVector3(boresight, "boresight");
  options.nav_to_camera.time_offset_s = time_offset;
  options.Check();
  return options;
}

std::string NavFlags::Describe() const {
  std::ostringstream text;
  text << "mount " << mount << ", lever arm " << lever_arm << " m, boresight "
       << boresight << " deg, time offset " << time_offset << " s";
  return text.str();
}

}  // namespace uw
