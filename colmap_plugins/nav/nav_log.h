// A navigation log of any format we read: nav.csv (nav_csv.h), NMEA 0183
// (nmea.h) or a Water Linked UGPS log (ugps_csv.h), chosen by --nav_format
// or by the file's first line.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "colmap_plugins/nav/geodesy.h"
#include "colmap_plugins/nav/nav_csv.h"
#include "colmap_plugins/nav/nmea.h"
#include "colmap_plugins/nav/ugps_csv.h"

namespace uw {

enum class NavLogFormat { kAuto, kCsv, kNmea, kWaterLinked };
std::string NavLogFormatName(NavLogFormat format);
// Throws uw::Error naming the accepted names.
NavLogFormat NavLogFormatFromName(const std::string& name);

struct NavLogOptions {
  // kAuto: NMEA when the first line that is not blank or a comment holds a
  // sentence (LooksLikeNmea), Water Linked when it is a header naming
  // position_valid,x,y,z,timestamp (LooksLikeUgpsLog), nav.csv otherwise.
  NavLogFormat format = NavLogFormat::kAuto;
  // A geographic log's local frame origin; none: AutomaticOrigin of its
  // first fix.
  std::optional<GeoOrigin> origin;
  NmeaOptions nmea;
  UgpsOptions ugps;  // only read for a Water Linked log
  // An export's column names (--columns lat=Latitude,...): only for a CSV.
  NavColumnMap columns;
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
