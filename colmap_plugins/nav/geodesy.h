// Geographic positions (WGS84 latitude/longitude, UTM) into the local
// metric frame the adjuster works in: east, north, up metres at an origin
// (GeographicLib's LocalCartesian, exact on the ellipsoid, not a flat-earth
// approximation). docs/formats.md, "Geographic logs".
#pragma once

#include <string>

#include <Eigen/Core>
#include <GeographicLib/LocalCartesian.hpp>

namespace uw {

// Where the local frame's (0, 0, 0) is: the log's vertical datum at
// height_m (0: the datum itself, e.g. the sea surface for depths).
struct GeoOrigin {
  double lat_deg = 0.0;
  double lon_deg = 0.0;
  double height_m = 0.0;

  // Finite, |lat| <= 90, lon in [-180, 360).
  void Check() const;
};

// "lat,lon" or "lat,lon,height" in degrees and metres, as --origin takes
// it. Throws uw::Error naming `source` on anything else.
GeoOrigin GeoOriginFromText(const std::string& text, const std::string& source);
// The same text with every digit that matters (1e-9 deg is 0.1 mm).
std::string GeoOriginText(const GeoOrigin& origin);

// The origin of a log that states none: its first fix rounded to 1e-3 deg
// (about 100 m), so that re-exports of one dive share a frame; height 0.
GeoOrigin AutomaticOrigin(double lat_deg, double lon_deg);

// Local east-north-up (metres) at an origin.
class LocalEnu {
 public:
  explicit LocalEnu(const GeoOrigin& origin);

  const GeoOrigin& Origin() const { return origin_; }
  Eigen::Vector3d FromGeodetic(double lat_deg, double lon_deg,
                               double height_m) const;
  // UTM: zone 1..60, north or south hemisphere.
  Eigen::Vector3d FromUtm(int zone, bool north, double easting_m,
                          double northing_m, double height_m) const;
  // Back to latitude, longitude (deg) and height (m): what uwsim writes.
  Eigen::Vector3d ToGeodetic(const Eigen::Vector3d& enu) const;

  // A heading (deg, clockwise from true north at the fix) as a yaw (deg,
  // counter-clockwise from the origin's east). North at a fix 10 km east
  // of the origin is turned by the meridians' convergence (0.09 deg at
  // 45 deg latitude), which this includes; the tilt of the fix's vertical
  // (10 km away: 0.09 deg) is left in roll and pitch.
  double YawFromHeading(double heading_deg, double lat_deg, double lon_deg,
                        double height_m) const;
  // Its inverse at a fix given in the local frame.
  double HeadingFromYaw(double yaw_deg, const Eigen::Vector3d& enu) const;

 private:
  GeoOrigin origin_;
  GeographicLib::LocalCartesian local_;
};

// "31n", "31N", "31north", "5s" ... (GeographicLib's UTMUPS::DecodeZone; "s"
// is the southern hemisphere, not latitude band S). Throws uw::Error naming
// `where` on a zone that is not UTM.
void ParseUtmZone(const std::string& text, const std::string& where, int* zone,
                  bool* north);

}  // namespace uw
