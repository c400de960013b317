#include "colmap_plugins/nav/geodesy.h"

#include <cmath>
#include <vector>

#include <fmt/format.h>
#include <GeographicLib/Constants.hpp>
#include <GeographicLib/UTMUPS.hpp>

#include "common/util/error.h"
#include "common/util/number_text.h"

namespace uw {

void GeoOrigin::Check() const {
  if (!std::isfinite(lat_deg) || !std::isfinite(lon_deg) ||
      !std::isfinite(height_m)) {
    throw ErrorAt("origin ", GeoOriginText(*this), " is not finite");
  }
  if (std::abs(lat_deg) > 90.0) {
    throw ErrorAt("origin latitude ", lat_deg,
                  " deg lies outside [-90, 90]: latitude first, then "
                  "longitude");
  }
  if (lon_deg < -180.0 || lon_deg >= 360.0) {
    throw ErrorAt("origin longitude ", lon_deg,
                  " deg lies outside [-180, 360)");
  }
}

GeoOrigin GeoOriginFromText(const std::string& text,
                            const std::string& source) {
  const std::optional<std::vector<double>> read = FiniteDoubles(text);
  if (!read || (read->size() != 2 && read->size() != 3)) {
    throw ErrorAt(source, ": '", text,
                  "' is not lat,lon or lat,lon,height (degrees, metres)");
  }
  const std::vector<double>& values = *read;
  GeoOrigin origin{values[0], values[1], values.size() == 3 ? values[2] : 0.0};
  try {
    origin.Check();
  } catch (const Error& error) {
    throw ErrorAt(source, ": ", error.what());
  }
  return origin;
}

std::string GeoOriginText(const GeoOrigin& origin) {
  return fmt::format("{:.9f},{:.9f},{:.4f}", origin.lat_deg, origin.lon_deg,
                     origin.height_m);
}

GeoOrigin AutomaticOrigin(double lat_deg, double lon_deg) {
  GeoOrigin origin{std::round(lat_deg * 1e3) / 1e3,
                   std::round(lon_deg * 1e3) / 1e3, 0.0};
  origin.Check();
  return origin;
}

LocalEnu::LocalEnu(const GeoOrigin& origin)
    : origin_(origin),
      local_(origin.lat_deg, origin.lon_deg, origin.height_m,
             GeographicLib::Geocentric::WGS84()) {
  origin.Check();
}

Eigen::Vector3d LocalEnu::FromGeodetic(double lat_deg, double lon_deg,
                                       double height_m) const {
  Eigen::Vector3d enu;
  local_.Forward(lat_deg, lon_deg, height_m, enu.x(), enu.y(), enu.z());
  return enu;
}

Eigen::Vector3d LocalEnu::FromUtm(int zone, bool north, double easting_m,
                                  double northing_m, double height_m) const {
  double lat = 0.0;
  double lon = 0.0;
  GeographicLib::UTMUPS::Reverse(zone, north, easting_m, northing_m, lat, lon);
  return FromGeodetic(lat, lon, height_m);
}

Eigen::Vector3d LocalEnu::ToGeodetic(const Eigen::Vector3d& enu) const {
  Eigen::Vector3d geodetic;
  local_.Reverse(enu.x(), enu.y(), enu.z(), geodetic(0), geodetic(1),
                 geodetic(2));
  return geodetic;
}

namespace {

// The rotation from the ENU frame at a fix to the origin's ENU frame
// (GeographicLib: v_origin = M v_fix).
Eigen::Matrix3d OriginFromFix(const GeographicLib::LocalCartesian& local,
                              double lat_deg, double lon_deg, double height_m) {
  std::vector<double> m(9);
  double x = 0.0;
  double y = 0.0;
  double z = 0.0;
  local.Forward(lat_deg, lon_deg, height_m, x, y, z, m);
  Eigen::Matrix3d rotation;
  rotation << m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8];
  return rotation;
}

constexpr double kDegToRad = M_PI / 180.0;

}  // namespace

double LocalEnu::YawFromHeading(double heading_deg, double lat_deg,
                                double lon_deg, double height_m) const {
  const double heading = heading_deg * kDegToRad;
  const Eigen::Vector3d forward_at_fix(std::sin(heading), std::cos(heading),
                                       0.0);
  const Eigen::Vector3d forward =
      OriginFromFix(local_, lat_deg, lon_deg, height_m) * forward_at_fix;
  return std::atan2(forward.y(), forward.x()) / kDegToRad;
}

double LocalEnu::HeadingFromYaw(double yaw_deg,
                                const Eigen::Vector3d& enu) const {
  // The heading whose YawFromHeading is yaw_deg: its forward vector, carried
  // into the origin's frame, lies in the vertical plane of the yaw, on its
  // forward side (the fix's horizontal plane is tilted against the
  // origin's, so the inverse is not just the transposed rotation).
  const Eigen::Vector3d fix = ToGeodetic(enu);
  const Eigen::Matrix3d origin_from_fix =
      OriginFromFix(local_, fix(0), fix(1), fix(2));
  const double yaw = yaw_deg * kDegToRad;
  const Eigen::Vector3d normal =
      origin_from_fix.transpose() *
      Eigen::Vector3d(-std::sin(yaw), std::cos(yaw), 0.0);
  double heading = std::atan2(-normal.y(), normal.x());
  const Eigen::Vector3d forward =
      origin_from_fix *
      Eigen::Vector3d(std::sin(heading), std::cos(heading), 0.0);
  if (forward.dot(Eigen::Vector3d(std::cos(yaw), std::sin(yaw), 0.0)) < 0.0) {
    heading += M_PI;
  }
  return std::remainder(heading / kDegToRad, 360.0);
}

void ParseUtmZone(const std::string& text, const std::string& where, int* zone,
                  bool* north) {
  try {
    GeographicLib::UTMUPS::DecodeZone(text, *zone, *north);
  } catch (const std::exception&) {
    *zone = GeographicLib::UTMUPS::INVALID;
  }
  if (*zone < GeographicLib::UTMUPS::MINUTMZONE ||
      *zone > GeographicLib::UTMUPS::MAXUTMZONE) {
    throw ErrorAt(where, ": zone '", text,
                  "' is not a UTM zone with its hemisphere (31n, 31s, "
                  "31north; a latitude band letter is not a hemisphere)");
  }
}

}  // namespace uw
