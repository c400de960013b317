// A navigation log of any format we read: nav.csv (nav_csv.h) or NMEA 0183
// (nmea.h), chosen by --nav_format or by the file's first line.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "colmap_plugins/nav/geodesy.h"
#include "colmap_plugins/nav/nav_csv.h"
#include "colmap_plugins/nav/nmea.h"

namespace uw {

enum class NavLogFormat { kAuto, kCsv, kNmea };
std::string NavLogFormatName(NavLogFormat format);
// Throws uw::Error naming the accepted names.
NavLogFormat NavLogFormatFromName(const std::string& name);

struct NavLogOptions {
  // kAuto: NMEA when the first line that is not blank or a comment holds a
  // sentence (LooksLikeNmea), nav.csv otherwise.
  NavLogFormat format = NavLogFormat::kAuto;
  // A geographic log's local frame origin; none: AutomaticOrigin of its
  // first fix.
  std::optional<GeoOrigin> origin;
  NmeaOptions nmea;
  // Seconds east of UTC of the clock that wrote ISO 8601 times without a
  // zone (nav.csv and image_times.csv); none: such times are an error.
  std::optional<int> time_zone_offset_s;

  void Check() const;
};

// The log's records in the local frame, and that frame in `frame`.
std::vector<NavRecord> ReadNavigationLog(const std::filesystem::path& path,
                                         const NavLogOptions& options,
                                         NavLogFrame* frame = nullptr);

}  // namespace uw
