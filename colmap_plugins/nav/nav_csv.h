// nav.csv, the navigation log (docs/formats.md): per row the vehicle's
// position and attitude at a time, with their standard deviations.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "colmap_plugins/nav/geodesy.h"

namespace uw {

struct NavRecord {
  // Empty when the log has no image_name column (a log sampled at its own
  // times; images then get their times from image_times.csv).
  std::string image_name;
  double time_s = 0.0;
  int dive = 1;  // 1 when the log has no dive column
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // vehicle, world, m
  Eigen::Vector3d rpy_rad = Eigen::Vector3d::Zero();   // attitude.h
  // 0: not stated (a log without std_x, std_y, std_z).
  Eigen::Vector3d position_sigma = Eigen::Vector3d::Zero();  // m, world axes
  Eigen::Vector3d rpy_sigma_rad = Eigen::Vector3d::Zero();
  // Whether the log has roll and pitch, and yaw (or heading): most USBL
  // exports have neither. What was not logged reads 0 above and means
  // nothing: camera_prior.h says what a prior then holds.
  bool has_roll_pitch = true;
  bool has_yaw = true;
  int line = 0;  // 1-based line in the file, for messages
};

// The frame a log's positions were read into.
struct NavLogFrame {
  // "x,y,z", "lat,lon,depth", "lat,lon,alt", "easting,northing,zone,depth",
  // "easting,northing,zone,alt" or "NMEA GGA".
  std::string position_columns;
  // A geographic log's records are in the local east-north-up frame (m)
  // at this origin: the one given, or AutomaticOrigin of its first row.
  std::optional<GeoOrigin> origin;
  bool origin_automatic = false;
  // What the reader left out and the user should hear of (NMEA fixes
  // without a fix, ...), each naming the file.
  std::vector<std::string> notes;
};

// Our names for an export's columns: (ours, the file's) pairs.
using NavColumnMap = std::vector<std::pair<std::string, std::string>>;

// "lat=Latitude,lon=Longitude,depth=Depth (m),time=timestamp" as --columns
// takes it: each of our nav.csv columns (ReadNavigationCsv) with the
// file's name for it. Throws uw::Error naming `source` on a name that is
// not ours, one given twice, or a pair without '='.
NavColumnMap NavColumnMapFromText(const std::string& text,
                                  const std::string& source);
std::string NavColumnMapText(const NavColumnMap& map);

// Reads nav.csv strictly: the header names the column time, one set of
// position columns, and optionally image_name, dive, roll and pitch
// (together), yaw or heading (clockwise from north: yaw = 90 - heading),
// and the sigmas std_x, std_y, std_z (together; east, north, up for a
// geographic log), std_roll, std_pitch (with roll, pitch) and std_yaw or
// std_heading (with yaw or heading), in any order. The position sets:
//   x,y,z                 metres, the world frame (z up)
//   lat,lon,depth | alt   WGS84 degrees; depth in m below, alt in m above
//                         the log's vertical datum
//   easting,northing,zone,depth | alt   UTM metres, zone as 31n or 31s
// A geographic log is read into LocalEnu at `origin` (AutomaticOrigin of
// its first row when not given); its heading or yaw is taken at each fix
// (LocalEnu::YawFromHeading). `origin` with an x,y,z log is an error.
// With `column_map`, an export's columns are read under our names and
// its other columns ignored (NavColumnMapFromText).
// `time` is seconds or ISO 8601 (ParseTimeField; a time without a zone is
// on the clock `time_zone_offset_s` east of UTC, an error when not given).
// Every value is a finite number, dives are integers >= 1, sigmas >= 0,
// image names are non-empty and unique, and within a dive the rows come in
// strictly increasing time. Sigmas not given read 0. Throws uw::Error
// naming the file and line. `frame`, when given, receives the frame.
std::vector<NavRecord> ReadNavigationCsv(
    const std::filesystem::path& path,
    const std::optional<GeoOrigin>& origin = std::nullopt,
    NavLogFrame* frame = nullptr,
    std::optional<int> time_zone_offset_s = std::nullopt,
    const NavColumnMap& column_map = {});

}  // namespace uw
