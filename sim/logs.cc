#include "sim/logs.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <GeographicLib/UTMUPS.hpp>

#include "colmap_plugins/nav/nmea.h"
#include "common/util/error.h"
#include "common/util/json_fields.h"
#include "common/util/time_text.h"

namespace uw::sim {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;
const std::vector<std::string> kNavFormats = {"wgs84", "utm", "nmea",
                                              "waterlinked"};

bool Has(const std::vector<std::string>& formats, const std::string& format) {
  return std::find(formats.begin(), formats.end(), format) != formats.end();
}

// NMEA's ddmm.mmmmmmmm (latitude) or dddmm.mmmmmmmm (longitude) and its
// hemisphere letter.
std::string NmeaAngle(double degrees, bool latitude) {
  const double magnitude = std::abs(degrees);
  double whole = std::floor(magnitude);
  double minutes = (magnitude - whole) * 60.0;
  // Rounding to the written decimals may carry into the degrees.
  if (std::round(minutes * 1e8) >= 60e8) {
    whole += 1.0;
    minutes = 0.0;
  }
  const char hemisphere =
      latitude ? (degrees < 0.0 ? 'S' : 'N') : (degrees < 0.0 ? 'W' : 'E');
  return fmt::format(latitude ? "{:02.0f}{:011.8f},{}" : "{:03.0f}{:011.8f},{}",
                     whole, minutes, hemisphere);
}

std::string Sentence(const std::string& body) {
  return fmt::format("${}*{:02X}\n", body, NmeaChecksum(body));
}

}  // namespace

void LogOptions::Check() const {
  if (!clock_start.empty()) ParseIsoTime(clock_start, "logs.clock_start");
  CameraZoneOffset();
  if (exif_times && clock_start.empty()) {
    throw ErrorAt(
        "logs.exif_times needs logs.clock_start: EXIF holds calendar times");
  }
  for (const std::string& format : nav_formats) {
    if (!Has(kNavFormats, format)) {
      throw ErrorAt("logs.nav_formats: unknown format '", format,
                    "' (wgs84, utm, nmea, waterlinked)");
    }
  }
  if (!nav_formats.empty() && geodetic_origin.empty()) {
    throw ErrorAt("logs.nav_formats needs logs.geodetic_origin (\"lat,lon\")");
  }
  if (!geodetic_origin.empty()) Origin(0.0);
  if (Has(nav_formats, "nmea") && clock_start.empty()) {
    throw ErrorAt(
        "logs.nav_formats \"nmea\" needs logs.clock_start: NMEA "
        "holds times of day and dates");
  }
  if (Has(nav_formats, "waterlinked")) {
    if (clock_start.empty()) {
      throw ErrorAt(
          "logs.nav_formats \"waterlinked\" needs "
          "logs.clock_start: its timestamps are Unix times");
    }
    UgpsTopsideFromText(ugps_topside, "logs.ugps_topside");
  }
}

std::optional<double> LogOptions::ClockStart() const {
  if (clock_start.empty()) return std::nullopt;
  return ParseIsoTime(clock_start, "logs.clock_start");
}

int LogOptions::CameraZoneOffset() const {
  return ParseZoneOffset(camera_zone, "logs.camera_zone");
}

GeoOrigin LogOptions::Origin(double site_depth_m) const {
  GeoOrigin origin = GeoOriginFromText(geodetic_origin, "logs.geodetic_origin");
  if (origin.height_m != 0.0) {
    throw ErrorAt(
        "logs.geodetic_origin is \"lat,lon\": the world origin's "
        "depth is navigation.site_depth_m");
  }
  origin.height_m = -site_depth_m;
  return origin;
}

void to_json(nlohmann::json& json, const LogOptions& options) {
  json = {{"clock_start", options.clock_start},
          {"exif_times", options.exif_times},
          {"camera_zone", options.camera_zone},
          {"geodetic_origin", options.geodetic_origin},
          {"nav_formats", options.nav_formats},
          {"ugps_topside", options.ugps_topside}};
}

void from_json(const nlohmann::json& json, LogOptions& options) {
  JsonFields fields(json, "logs");
  fields.Read("clock_start", &options.clock_start);
  fields.Read("exif_times", &options.exif_times);
  fields.Read("camera_zone", &options.camera_zone);
  fields.Read("geodetic_origin", &options.geodetic_origin);
  fields.Read("nav_formats", &options.nav_formats);
  fields.Read("ugps_topside", &options.ugps_topside);
  fields.RejectUnknown();
  options.Check();
}

double LogTime(const std::optional<double>& clock_start_s, double survey_s) {
  return clock_start_s ? *clock_start_s + survey_s : survey_s;
}

std::string LogTimeUnits(const std::optional<double>& clock_start_s) {
  return clock_start_s ? "Unix time (s since 1970-01-01T00:00:00Z)"
                       : "seconds since the survey's start";
}

std::string GeographicNavigationCsv(
    const std::vector<NavigationRecord>& records, const LocalEnu& local,
    bool utm) {
  std::string text = fmt::format(
      "# uwsim navigation, WGS84{}: depth in m below the datum, heading in "
      "deg clockwise from north at each fix, roll and pitch in deg; read at "
      "--origin {} it is nav.csv's frame; time as in nav.csv\n"
      "image_name,time,dive,{},depth,roll,pitch,heading,std_x,std_y,std_z,"
      "std_roll,std_pitch,std_heading\n",
      utm ? " UTM" : " latitude/longitude", GeoOriginText(local.Origin()),
      utm ? "easting,northing,zone" : "lat,lon");
  for (const NavigationRecord& record : records) {
    const Eigen::Vector3d fix = local.ToGeodetic(record.position);
    std::string where = fmt::format("{:.17g},{:.17g}", fix(0), fix(1));
    if (utm) {
      int zone = 0;
      bool north = true;
      double easting = 0.0;
      double northing = 0.0;
      GeographicLib::UTMUPS::Forward(fix(0), fix(1), zone, north, easting,
                                     northing);
      where = fmt::format("{:.17g},{:.17g},{}{}", easting, northing, zone,
                          north ? "n" : "s");
    }
    const double heading =
        local.HeadingFromYaw(record.rpy(2) * kRadToDeg, record.position);
    text += fmt::format("{},{:.17g},{},{},{:.17g}", record.image_name,
                        record.time_s, record.dive, where, -fix(2));
    for (const double value :
         {record.rpy(0) * kRadToDeg, record.rpy(1) * kRadToDeg, heading,
          record.position_sigma(0), record.position_sigma(1),
          record.position_sigma(2), record.rpy_sigma(0) * kRadToDeg,
          record.rpy_sigma(1) * kRadToDeg, record.rpy_sigma(2) * kRadToDeg}) {
      text += fmt::format(",{:.17g}", value);
    }
    text += "\n";
  }
  return text;
}

std::string WaterLinkedNavigationLog(
    const std::vector<NavigationRecord>& records, const LocalEnu& local,
    const UgpsTopside& topside) {
  const LocalEnu at_topside(GeoOrigin{topside.lat_deg, topside.lon_deg, 0.0});
  const double h = topside.heading_deg / kRadToDeg;
  std::string text = "position_valid,std,x,y,z,timestamp\n";
  for (const NavigationRecord& record : records) {
    const Eigen::Vector3d fix = local.ToGeodetic(record.position);
    const Eigen::Vector3d enu = at_topside.FromGeodetic(fix(0), fix(1), fix(2));
    text += fmt::format(
        "True,{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}\n",
        record.position_sigma(0), enu.x() * std::sin(h) + enu.y() * std::cos(h),
        enu.x() * std::cos(h) - enu.y() * std::sin(h), -enu.z(), record.time_s);
  }
  return text;
}

std::string NmeaNavigationLog(const std::vector<NavigationRecord>& records,
                              const LocalEnu& local) {
  std::string text = fmt::format(
      "# uwsim navigation as NMEA 0183; read at --origin {} it is nav.csv's "
      "frame\n",
      GeoOriginText(local.Origin()));
  double day = std::nan("");
  for (const NavigationRecord& record : records) {
    // Whole microseconds, so that the time of day and the date agree.
    constexpr long long kDay = 86400000000LL;
    const long long micros = std::llround(record.time_s * 1e6);
    const long long midnight_us = micros - ((micros % kDay) + kDay) % kDay;
    const long long of_day = micros - midnight_us;
    const int hours = static_cast<int>(of_day / 3600000000LL);
    const int minutes = static_cast<int>(of_day / 60000000LL % 60);
    const double seconds = static_cast<double>(of_day % 60000000LL) / 1e6;
    const double midnight = static_cast<double>(midnight_us / 1000000LL);
    if (midnight != day) {
      day = midnight;
      // IsoTimeText gives the calendar date: "2024-10-08T...".
      const std::string date = IsoTimeText(midnight, 0, 0);
      text += Sentence(fmt::format("GPZDA,{:02d}{:02d}{:09.6f},{},{},{},00,00",
                                   hours, minutes, seconds, date.substr(8, 2),
                                   date.substr(5, 2), date.substr(0, 4)));
    }
    const Eigen::Vector3d fix = local.ToGeodetic(record.position);
    // A compass's heading, 0 to 360.
    const double heading =
        local.HeadingFromYaw(record.rpy(2) * kRadToDeg, record.position);
    text += Sentence(fmt::format("HEHDT,{:.8f},T",
                                 heading < 0.0 ? heading + 360.0 : heading));
    text += Sentence(fmt::format(
        "GPGGA,{:02d}{:02d}{:09.6f},{},{},1,12,0.8,{:.6f},M,0.0,M,,", hours,
        minutes, seconds, NmeaAngle(fix(0), true), NmeaAngle(fix(1), false),
        fix(2)));
  }
  return text;
}

}  // namespace uw::sim
