#include "colmap_plugins/nav/ugps_csv.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "common/util/csv.h"
#include "common/util/error.h"
#include "common/util/number_text.h"
#include "common/util/time_text.h"

namespace uw {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

void RequireColumns(const CsvTable& table,
                    const std::vector<std::string>& columns,
                    const std::string& what) {
  for (const std::string& column : columns) {
    if (!table.HasColumn(column)) {
      throw ErrorAt(table.Path().string(), ":1: a ", what,
                    " needs the column '", column, "'");
    }
  }
}

bool IsTrue(const std::string& text, const std::string& where) {
  if (text == "True" || text == "true" || text == "1") return true;
  if (text == "False" || text == "false" || text == "0") return false;
  throw ErrorAt(where, ": position_valid must be True or False, got '", text,
                "'");
}

std::vector<UgpsTopside> ReadMasterLog(const std::filesystem::path& path) {
  const CsvTable table = CsvTable::Read(path);
  RequireColumns(table, {"timestamp", "lat", "lon", "orientation"},
                 "Water Linked topside (position/master) log");
  std::vector<UgpsTopside> fixes;
  for (size_t row = 0; row < table.NumRows(); ++row) {
    UgpsTopside fix;
    fix.time_s = table.Time(row, "timestamp");
    fix.lat_deg = table.Double(row, "lat");
    fix.lon_deg = table.Double(row, "lon");
    fix.heading_deg = table.Double(row, "orientation");
    if (std::abs(fix.lat_deg) > 90.0 || std::abs(fix.lon_deg) > 360.0) {
      throw ErrorAt(table.Where(row), ": lat,lon ", fix.lat_deg, ",",
                    fix.lon_deg, " is not a position in degrees");
    }
    // The API's -1: no compass reading.
    if (fix.heading_deg < 0.0) continue;
    if (!fixes.empty() && !(fix.time_s > fixes.back().time_s)) {
      throw ErrorAt(table.Where(row), ": timestamp ", TimeText(fix.time_s),
                    " is not after the previous row's");
    }
    fixes.push_back(fix);
  }
  if (fixes.empty()) throw ErrorAt(path.string(), ": no topside fix");
  return fixes;
}

// The topside at `time`: linear in lat, lon and the heading's shorter arc
// (fixes a second or so apart, metres apart).
std::optional<UgpsTopside> TopsideAt(const std::vector<UgpsTopside>& fixes,
                                     double time) {
  if (fixes.size() == 1) {
    if (time != fixes[0].time_s) return std::nullopt;
    return fixes[0];
  }
  if (time < fixes.front().time_s || time > fixes.back().time_s) {
    return std::nullopt;
  }
  const auto after = std::upper_bound(
      fixes.begin(), fixes.end(), time,
      [](double t, const UgpsTopside& fix) { return t < fix.time_s; });
  const UgpsTopside& b = after == fixes.end() ? fixes.back() : *after;
  const UgpsTopside& a = after == fixes.end() ? *(after - 2) : *(after - 1);
  const double f = (time - a.time_s) / (b.time_s - a.time_s);
  UgpsTopside fix;
  fix.time_s = time;
  fix.lat_deg = a.lat_deg + f * (b.lat_deg - a.lat_deg);
  fix.lon_deg = a.lon_deg + f * (b.lon_deg - a.lon_deg);
  fix.heading_deg =
      a.heading_deg + f * std::remainder(b.heading_deg - a.heading_deg, 360.0);
  return fix;
}

}  // namespace

void UgpsOptions::Check() const {
  if (topside.has_value() == !master_path.empty()) {
    throw ErrorAt(
        "a Water Linked log is relative to its topside: give either "
        "--ugps_topside lat,lon,heading (a topside that did not move) or "
        "--ugps_master (its position/master log)");
  }
}

UgpsTopside UgpsTopsideFromText(const std::string& text,
                                const std::string& source) {
  const std::vector<double> values =
      FiniteDoubles(text).value_or(std::vector<double>());
  if (values.size() != 3 || std::abs(values[0]) > 90.0 ||
      std::abs(values[1]) > 360.0) {
    throw ErrorAt(source, " '", text,
                  "': expected lat,lon,heading in degrees (e.g. "
                  "43.2951,5.3612,35)");
  }
  return UgpsTopside{0.0, values[0], values[1], values[2]};
}

bool LooksLikeUgpsLog(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    const size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::vector<std::string> names;
    std::stringstream stream(line);
    std::string name;
    while (std::getline(stream, name, ',')) {
      name.erase(std::remove_if(name.begin(), name.end(),
                                [](char c) { return c == '"' || c == '\r'; }),
                 name.end());
      names.push_back(name);
    }
    for (const char* needed : {"position_valid", "x", "y", "z", "timestamp"}) {
      if (std::find(names.begin(), names.end(), needed) == names.end()) {
        return false;
      }
    }
    return true;
  }
  return false;
}

std::vector<NavRecord> ReadUgpsLog(const std::filesystem::path& path,
                                   const UgpsOptions& options,
                                   const std::optional<GeoOrigin>& origin,
                                   NavLogFrame* frame) {
  options.Check();
  const std::vector<UgpsTopside> master =
      options.topside ? std::vector<UgpsTopside>{}
                      : ReadMasterLog(options.master_path);
  const CsvTable table = CsvTable::Read(path);
  RequireColumns(table, {"timestamp", "x", "y", "z"},
                 "Water Linked acoustic log");
  const bool has_std = table.HasColumn("std");
  const bool has_valid = table.HasColumn("position_valid");
  NavLogFrame read_frame;
  read_frame.position_columns = "Water Linked x,y,z";
  const UgpsTopside first = options.topside ? *options.topside : master[0];
  read_frame.origin =
      origin ? *origin : AutomaticOrigin(first.lat_deg, first.lon_deg);
  read_frame.origin_automatic = !origin;
  const LocalEnu local(*read_frame.origin);
  std::vector<NavRecord> records;
  size_t invalid = 0;
  for (size_t row = 0; row < table.NumRows(); ++row) {
    const std::string where = table.Where(row);
    if (has_valid && !IsTrue(table.Text(row, "position_valid"), where)) {
      ++invalid;
      continue;
    }
    NavRecord record;
    record.line = table.Line(row);
    record.time_s = table.Time(row, "timestamp");
    if (!records.empty() && !(record.time_s > records.back().time_s)) {
      throw ErrorAt(where, ": timestamp ", TimeText(record.time_s),
                    " is not after the previous row's (line ",
                    records.back().line, ", ", TimeText(records.back().time_s),
                    ")");
    }
    std::optional<UgpsTopside> topside = options.topside;
    if (!topside) {
      topside = TopsideAt(master, record.time_s);
      if (!topside) {
        throw ErrorAt(where, ": timestamp ", TimeText(record.time_s),
                      " lies outside the topside log ", options.master_path,
                      " (", TimeText(master.front().time_s), " to ",
                      TimeText(master.back().time_s), ")");
      }
    }
    // East-north-up at the topside: x along its heading h (clockwise from
    // north), y 90 deg clockwise of it; then through the ellipsoid into the
    // log's frame, exact however far the topside is from the origin.
    const double h = topside->heading_deg * kDegToRad;
    const double x = table.Double(row, "x");
    const double y = table.Double(row, "y");
    const Eigen::Vector3d at_topside(x * std::sin(h) + y * std::cos(h),
                                     x * std::cos(h) - y * std::sin(h),
                                     -table.Double(row, "z"));
    const Eigen::Vector3d fix =
        LocalEnu(GeoOrigin{topside->lat_deg, topside->lon_deg, 0.0})
            .ToGeodetic(at_topside);
    record.position = local.FromGeodetic(fix(0), fix(1), fix(2));
    if (has_std) {
      record.position_sigma.setConstant(table.NonNegativeDouble(row, "std"));
    }
    record.has_roll_pitch = false;
    record.has_yaw = false;
    records.push_back(record);
  }
  if (records.empty()) {
    throw ErrorAt(path.string(), ": no valid position (", invalid,
                  " rows with position_valid False)");
  }
  if (invalid > 0) {
    read_frame.notes.push_back(
        fmt::format("{}: {} rows with position_valid False left out",
                    path.string(), invalid));
  }
  if (frame != nullptr) *frame = read_frame;
  return records;
}

}  // namespace uw
