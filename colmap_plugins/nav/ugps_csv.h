// Water Linked Underwater GPS logs: the locator's acoustic position as the
// topside unit gives it (GET /api/v1/position/acoustic/filtered or /raw),
// one row per poll, as loggers write it (e.g. wl_ugps_logger.py of
// ardusub_log_tools: the JSON keys as columns plus a Unix `timestamp`).
// The position is relative to the topside ("master electronics") in its own
// frame: x forward (the arrow on the topside housing, whose compass heading
// the topside reports as `orientation`), y to starboard, z the depth. With
// the topside's latitude, longitude and heading (fixed, or from a log of
// GET /api/v1/position/master) each row becomes a position in the local
// east-north-up frame. docs/formats.md, "Water Linked UGPS logs".
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "colmap_plugins/nav/geodesy.h"
#include "colmap_plugins/nav/nav_csv.h"

namespace uw {

// The topside at one time: WGS84 degrees, heading in deg clockwise from
// true north.
struct UgpsTopside {
  double time_s = 0.0;
  double lat_deg = 0.0;
  double lon_deg = 0.0;
  double heading_deg = 0.0;
};

struct UgpsOptions {
  // A topside that did not move (a dock, an anchored boat): "lat,lon,
  // heading" as --ugps_topside takes it.
  std::optional<UgpsTopside> topside;
  // Or a log of the topside (timestamp,lat,lon,orientation, any other
  // columns ignored), interpolated at each acoustic row's time.
  std::string master_path;

  // Exactly one of the two. Throws uw::Error.
  void Check() const;
};

// "lat,lon,heading" (deg). Throws uw::Error naming `source`.
UgpsTopside UgpsTopsideFromText(const std::string& text,
                                const std::string& source);

// Whether `path` is a Water Linked acoustic log: a CSV whose header (the
// first line that is not blank or a comment) names position_valid, x, y,
// z and timestamp.
bool LooksLikeUgpsLog(const std::filesystem::path& path);

// The log's rows as navigation records in the local east-north-up frame at
// `origin` (AutomaticOrigin of the first topside fix when not given):
// position = topside + x forward + y starboard (turned by the topside's
// heading at its fix) and -z up, the topside at the datum (height 0). No
// attitude; `std` (m), when present, as the sigma of each axis. Rows with
// position_valid false are left out (counted in frame->notes); times must
// increase. Rows outside the master log's span are an error naming the
// row. Throws uw::Error naming the file and line.
std::vector<NavRecord> ReadUgpsLog(const std::filesystem::path& path,
                                   const UgpsOptions& options,
                                   const std::optional<GeoOrigin>& origin,
                                   NavLogFrame* frame);

}  // namespace uw
