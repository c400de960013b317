#include "colmap_plugins/nav/nav_csv.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

#include <GeographicLib/UTMUPS.hpp>

#include "common/util/csv.h"
#include "common/util/error.h"
#include "common/util/time_text.h"

namespace uw {

namespace {

enum class PositionColumns { kCartesian, kLatLon, kUtm };

// The one set of position columns the header has, named in the frame.
PositionColumns ChoosePositionColumns(const CsvTable& table,
                                      NavLogFrame* frame) {
  const std::string file = table.Path().string() + ":1: ";
  const auto has = [&](const char* name) { return table.HasColumn(name); };
  const int sets = (has("x") || has("y") || has("z")) +
                   (has("lat") || has("lon")) +
                   (has("easting") || has("northing") || has("zone"));
  const bool complete = (has("x") && has("y") && has("z")) ||
                        (has("lat") && has("lon")) ||
                        (has("easting") && has("northing") && has("zone"));
  const bool vertical = has("depth") || has("alt");
  const bool geographic = !has("x") && !has("y") && !has("z");
  if (sets != 1 || !complete || (geographic && !vertical) ||
      (!geographic && vertical) || (has("depth") && has("alt"))) {
    throw ErrorAt(
        file,
        "the positions are one of x,y,z (m) | lat,lon,depth | "
        "lat,lon,alt (WGS84 deg, m) | easting,northing,zone,depth | "
        "easting,northing,zone,alt (UTM m, zone as 31n); the "
        "header has ",
        [&] {
          std::string names;
          for (const char* name : {"x", "y", "z", "lat", "lon", "easting",
                                   "northing", "zone", "depth", "alt"}) {
            if (has(name)) {
              names += (names.empty() ? "" : ",") + std::string(name);
            }
          }
          return names.empty() ? std::string("none") : names;
        }());
  }
  const std::string height = has("depth") ? "depth" : "alt";
  if (has("x")) {
    frame->position_columns = "x,y,z";
    return PositionColumns::kCartesian;
  }
  if (has("lat")) {
    frame->position_columns = "lat,lon," + height;
    return PositionColumns::kLatLon;
  }
  frame->position_columns = "easting,northing,zone," + height;
  return PositionColumns::kUtm;
}

// Columns that come together or not at all, and columns that need another:
// a header breaking either rule is refused before any row is read.
void CheckColumnSets(const CsvTable& table) {
  const std::string file = table.Path().string() + ":1: ";
  const auto has = [&](const char* name) { return table.HasColumn(name); };
  for (const std::vector<const char*>& together :
       {std::vector<const char*>{"roll", "pitch"},
        {"std_x", "std_y", "std_z"},
        {"std_roll", "std_pitch"}}) {
    const size_t count = static_cast<size_t>(
        std::count_if(together.begin(), together.end(), has));
    if (count != 0 && count != together.size()) {
      std::string names;
      for (const char* name : together) {
        names += (names.empty() ? "" : ", ") + std::string(name);
      }
      throw ErrorAt(file, "the columns ", names,
                    " come together or not at all");
    }
  }
  if (has("yaw") && has("heading")) {
    throw ErrorAt(file, "yaw and heading say the same; give one");
  }
  if (has("std_yaw") && has("std_heading")) {
    throw ErrorAt(file, "std_yaw and std_heading say the same; give one");
  }
  if (has("std_roll") && !has("roll")) {
    throw ErrorAt(file,
                  "std_roll and std_pitch are the sigmas of roll and "
                  "pitch, which the log does not have");
  }
  for (const char* sigma : {"std_yaw", "std_heading"}) {
    if (has(sigma) && !has("yaw") && !has("heading")) {
      throw ErrorAt(file, sigma,
                    " is the sigma of yaw or heading, which the "
                    "log does not have");
    }
  }
}

// Every column nav.csv may have.
const std::vector<std::string>& NavCsvColumns() {
  static const std::vector<std::string> columns = {
      "image_name", "time",  "dive",     "x",         "y",       "z",
      "lat",        "lon",   "depth",    "alt",       "easting", "northing",
      "zone",       "roll",  "pitch",    "yaw",       "heading", "std_x",
      "std_y",      "std_z", "std_roll", "std_pitch", "std_yaw", "std_heading"};
  return columns;
}

}  // namespace

NavColumnMap NavColumnMapFromText(const std::string& text,
                                  const std::string& source) {
  NavColumnMap map;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t comma = std::min(text.find(',', start), text.size());
    const std::string pair = text.substr(start, comma - start);
    const size_t equals = pair.find('=');
    if (equals == std::string::npos || equals == 0 ||
        equals + 1 == pair.size()) {
      throw ErrorAt(source, ": '", pair,
                    "' is not ours=theirs (e.g. lat=Latitude)");
    }
    const std::string ours = pair.substr(0, equals);
    const std::vector<std::string>& columns = NavCsvColumns();
    if (std::find(columns.begin(), columns.end(), ours) == columns.end()) {
      std::string names;
      for (const std::string& name : columns) {
        names += (names.empty() ? "" : ", ") + name;
      }
      throw ErrorAt(source, ": '", ours, "' is not a nav.csv column (", names,
                    ")");
    }
    for (const auto& [other, file] : map) {
      if (other == ours) throw ErrorAt(source, ": '", ours, "' given twice");
    }
    map.emplace_back(ours, pair.substr(equals + 1));
    start = comma + 1;
  }
  return map;
}

std::string NavColumnMapText(const NavColumnMap& map) {
  std::string text;
  for (const auto& [ours, file] : map) {
    text += (text.empty() ? "" : ",") + ours + "=" + file;
  }
  return text;
}

std::vector<NavRecord> ReadNavigationCsv(const std::filesystem::path& path,
                                         const std::optional<GeoOrigin>& origin,
                                         NavLogFrame* frame,
                                         std::optional<int> time_zone_offset_s,
                                         const NavColumnMap& column_map) {
  const std::vector<std::string>& columns = NavCsvColumns();
  const CsvTable table =
      column_map.empty() ? CsvTable::Read(path, columns, {"time"})
                         : CsvTable::Read(path, columns, {"time"}, column_map);
  NavLogFrame read_frame;
  const PositionColumns position_columns =
      ChoosePositionColumns(table, &read_frame);
  CheckColumnSets(table);
  if (table.NumRows() == 0) {
    throw ErrorAt(path.string(), ": no navigation rows");
  }
  const bool geographic = position_columns != PositionColumns::kCartesian;
  if (origin && !geographic) {
    throw ErrorAt(path.string(),
                  ": an origin is for a geographic log (lat/lon or UTM); this "
                  "one has x,y,z in metres already");
  }
  const std::string height_column = table.HasColumn("depth") ? "depth" : "alt";
  const double height_sign = table.HasColumn("depth") ? -1.0 : 1.0;
  // The fix of a row of a geographic log: lat, lon (deg), height (m).
  const auto fix_of = [&](size_t row) {
    const double height = height_sign * table.Double(row, height_column);
    if (position_columns == PositionColumns::kLatLon) {
      const double lat = table.Double(row, "lat");
      const double lon = table.Double(row, "lon");
      if (std::abs(lat) > 90.0 || lon < -180.0 || lon >= 360.0) {
        throw ErrorAt(table.Where(row), ": lat ", lat, ", lon ", lon,
                      " is not a position in degrees (lat within [-90, 90], "
                      "lon within [-180, 360))");
      }
      return Eigen::Vector3d(lat, lon, height);
    }
    int zone = 0;
    bool north = true;
    ParseUtmZone(table.Text(row, "zone"), table.Where(row), &zone, &north);
    Eigen::Vector3d fix(0.0, 0.0, height);
    try {
      GeographicLib::UTMUPS::Reverse(zone, north, table.Double(row, "easting"),
                                     table.Double(row, "northing"), fix(0),
                                     fix(1));
    } catch (const std::exception& error) {
      throw ErrorAt(table.Where(row), ": easting, northing not in zone ",
                    table.Text(row, "zone"), " (", error.what(), ")");
    }
    return fix;
  };
  std::optional<LocalEnu> local;
  if (geographic) {
    const Eigen::Vector3d first = fix_of(0);
    read_frame.origin = origin ? *origin : AutomaticOrigin(first(0), first(1));
    read_frame.origin_automatic = !origin;
    local.emplace(*read_frame.origin);
  }
  if (frame != nullptr) *frame = read_frame;
  const bool has_names = table.HasColumn("image_name");
  const bool has_dives = table.HasColumn("dive");
  const bool has_roll_pitch = table.HasColumn("roll");
  const bool has_heading = table.HasColumn("heading");
  const bool has_yaw = table.HasColumn("yaw") || has_heading;
  const std::string yaw_column = has_heading ? "heading" : "yaw";
  const bool has_position_sigma = table.HasColumn("std_x");
  const bool has_roll_pitch_sigma = table.HasColumn("std_roll");
  const std::string yaw_sigma_column =
      table.HasColumn("std_heading") ? "std_heading" : "std_yaw";
  const bool has_yaw_sigma = table.HasColumn(yaw_sigma_column);
  constexpr double kDegToRad = M_PI / 180.0;

  std::vector<NavRecord> records;
  std::unordered_map<std::string, int> line_of_image;
  std::map<int, size_t> last_of_dive;  // index of a dive's latest row
  records.reserve(table.NumRows());
  for (size_t row = 0; row < table.NumRows(); ++row) {
    NavRecord record;
    record.line = table.Line(row);
    const std::string where = table.Where(row);
    if (has_names) {
      record.image_name = table.Text(row, "image_name");
      if (record.image_name.empty()) throw ErrorAt(where, ": empty image_name");
    }
    record.time_s = table.Time(row, "time", time_zone_offset_s);
    if (has_dives) record.dive = table.Int(row, "dive", 1);
    record.has_roll_pitch = has_roll_pitch;
    record.has_yaw = has_yaw;
    Eigen::Vector3d fix = Eigen::Vector3d::Zero();
    if (geographic) {
      fix = fix_of(row);
      record.position = local->FromGeodetic(fix(0), fix(1), fix(2));
    }
    for (int k = 0; k < 3; ++k) {
      if (!geographic) {
        record.position(k) = table.Double(row, std::string(1, "xyz"[k]));
      }
      if (has_position_sigma) {
        record.position_sigma(k) =
            table.NonNegativeDouble(row, "std_" + std::string(1, "xyz"[k]));
      }
    }
    for (int k = 0; k < 2 && has_roll_pitch; ++k) {
      const std::string angle = k == 0 ? "roll" : "pitch";
      record.rpy_rad(k) = table.Double(row, angle) * kDegToRad;
      if (has_roll_pitch_sigma) {
        record.rpy_sigma_rad(k) =
            table.NonNegativeDouble(row, "std_" + angle) * kDegToRad;
      }
    }
    if (has_yaw) {
      // Heading turns clockwise from north (the y axis); yaw
      // counter-clockwise from east (x). A geographic log's are at the fix.
      const double value = table.Double(row, yaw_column);
      double yaw_deg = has_heading ? 90.0 - value : value;
      if (geographic) {
        yaw_deg = local->YawFromHeading(has_heading ? value : 90.0 - value,
                                        fix(0), fix(1), fix(2));
      }
      record.rpy_rad(2) = yaw_deg * kDegToRad;
      if (has_yaw_sigma) {
        record.rpy_sigma_rad(2) =
            table.NonNegativeDouble(row, yaw_sigma_column) * kDegToRad;
      }
    }
    if (has_names) {
      const auto [previous, inserted] =
          line_of_image.emplace(record.image_name, record.line);
      if (!inserted) {
        throw ErrorAt(where, ": image '", record.image_name,
                      "' already has a row at line ", previous->second);
      }
    }
    const auto previous = last_of_dive.find(record.dive);
    if (previous != last_of_dive.end() &&
        !(record.time_s > records[previous->second].time_s)) {
      const NavRecord& before = records[previous->second];
      throw ErrorAt(where, ": time ", TimeText(record.time_s),
                    " s is not after the previous row of dive ", record.dive,
                    " (line ", before.line, ", ", TimeText(before.time_s),
                    " s); the rows of a dive must come in strictly "
                    "increasing time");
    }
    last_of_dive[record.dive] = records.size();
    records.push_back(record);
  }
  return records;
}

}  // namespace uw
