// The survey's logs as vehicles and cameras write them: times on a real
// clock (Unix time from a stated start), capture times in the images' EXIF,
// and the navigation as WGS84 lat/lon/depth, UTM and NMEA 0183 besides the
// local nav.csv. They let tests check that each gives the local log's
// priors (docs/uwsim.md, "Logs").
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "colmap_plugins/nav/geodesy.h"
#include "colmap_plugins/nav/ugps_csv.h"
#include "sim/navigation.h"

namespace uw::sim {

struct LogOptions {
  // ISO 8601 time with its zone of the survey's start, e.g.
  // "2024-10-08T12:00:00Z": nav.csv, image_times.csv and
  // laser_image_times.csv then hold Unix times. Empty: seconds since the
  // start.
  std::string clock_start;
  // Write each image's capture time into its EXIF (DateTimeOriginal,
  // SubSecTimeOriginal to the microsecond, OffsetTimeOriginal) on a camera
  // clock set to `camera_zone` (cameras are often set to local time).
  // Needs clock_start.
  bool exif_times = false;
  std::string camera_zone = "+00:00";
  // "lat,lon" (deg) of the world origin x = y = 0, which lies
  // navigation.site_depth_m below the sea surface. Needed by the formats.
  std::string geodetic_origin;
  // Navigation logs written besides nav.csv, any of
  //   "wgs84"  nav_wgs84.csv: lat,lon,depth, roll,pitch,heading and sigmas
  //   "utm"    nav_utm.csv: easting,northing,zone,depth, the same angles
  //   "nmea"   nav.nmea: ZDA dates, HDT headings and GGA fixes (minutes to
  //            1e-8, 0.02 mm; seconds to 1e-6), as a GPS/USBL logger; needs
  //            clock_start
  //   "waterlinked"  nav_waterlinked.csv: a Water Linked UGPS acoustic log
  //            (position_valid,std,x,y,z,timestamp; x forward, y starboard
  //            of the topside at ugps_topside, z depth); needs clock_start
  std::vector<std::string> nav_formats;
  // "lat,lon,heading" (deg) of the Water Linked topside, which does not
  // move. Needed by "waterlinked".
  std::string ugps_topside;

  // Throws uw::Error naming the option.
  void Check() const;
  // The start as Unix time, or nullopt without clock_start.
  std::optional<double> ClockStart() const;
  // The camera clock's zone, seconds east of UTC.
  int CameraZoneOffset() const;
  // The frame of the geographic logs: at geodetic_origin, site_depth_m
  // below the datum, so that it is nav.csv's frame (read the logs with
  // --origin GeoOriginText(origin)).
  GeoOrigin Origin(double site_depth_m) const;
};
void to_json(nlohmann::json& json, const LogOptions& options);
void from_json(const nlohmann::json& json, LogOptions& options);

// A survey time (s since the start) on the logs' clock.
double LogTime(const std::optional<double>& clock_start_s, double survey_s);
// What the logs' times are, for their comment lines.
std::string LogTimeUnits(const std::optional<double>& clock_start_s);

// The navigation as a WGS84 (or UTM) nav.csv: each fix's heading taken
// clockwise from its own north, depths below the datum. `records` hold
// times on the logs' clock.
std::string GeographicNavigationCsv(
    const std::vector<NavigationRecord>& records, const LocalEnu& local,
    bool utm);

// The navigation as a Water Linked UGPS acoustic log relative to `topside`
// (ugps_csv.h): no attitude, names or dives; `std` the horizontal sigma.
// `records` hold Unix times.
std::string WaterLinkedNavigationLog(
    const std::vector<NavigationRecord>& records, const LocalEnu& local,
    const UgpsTopside& topside);

// The navigation as NMEA 0183 (GPZDA, HEHDT, GPGGA with the altitude above
// the datum); no roll, pitch, sigmas, dives or image names, as a logger
// writes it. `records` hold Unix times.
std::string NmeaNavigationLog(const std::vector<NavigationRecord>& records,
                              const LocalEnu& local);

}  // namespace uw::sim
