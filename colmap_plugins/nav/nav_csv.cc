#include "colmap_plugins/nav/nav_csv.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

#include "common/util/csv.h"
#include "common/util/error.h"
#include "common/util/time_text.h"

namespace uw {

namespace {

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

}  // namespace

std::vector<NavRecord> ReadNavigationCsv(const std::filesystem::path& path) {
  const std::vector<std::string> columns = {
      "image_name", "time",     "dive",      "x",       "y",          "z",
      "roll",       "pitch",    "yaw",       "heading", "std_x",      "std_y",
      "std_z",      "std_roll", "std_pitch", "std_yaw", "std_heading"};
  const CsvTable table = CsvTable::Read(path, columns, {"time", "x", "y", "z"});
  if (table.NumRows() == 0) {
    throw ErrorAt(path.string(), ": no navigation rows");
  }
  CheckColumnSets(table);
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
    record.time_s = table.Double(row, "time");
    if (has_dives) record.dive = table.Int(row, "dive", 1);
    record.has_roll_pitch = has_roll_pitch;
    record.has_yaw = has_yaw;
    for (int k = 0; k < 3; ++k) {
      record.position(k) = table.Double(row, columns[3 + k]);
      if (has_position_sigma) {
        record.position_sigma(k) =
            table.NonNegativeDouble(row, columns[10 + k]);
      }
    }
    for (int k = 0; k < 2 && has_roll_pitch; ++k) {
      record.rpy_rad(k) = table.Double(row, columns[6 + k]) * kDegToRad;
      if (has_roll_pitch_sigma) {
        record.rpy_sigma_rad(k) =
            table.NonNegativeDouble(row, columns[13 + k]) * kDegToRad;
      }
    }
    if (has_yaw) {
      // Heading turns clockwise from north (the y axis); yaw
      // counter-clockwise from east (x).
      const double yaw_deg = has_heading ? 90.0 - table.Double(row, yaw_column)
                                         : table.Double(row, yaw_column);
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
