#include "colmap_plugins/nav/nav_csv.h"

#include <cmath>
#include <map>
#include <unordered_map>

#include "common/util/csv.h"
#include "common/util/error.h"
#include "common/util/time_text.h"

namespace uw {

std::vector<NavRecord> ReadNavigationCsv(const std::filesystem::path& path) {
  const std::vector<std::string> columns = {
      "image_name", "time",  "dive",     "x",         "y",
      "z",          "roll",  "pitch",    "yaw",       "std_x",
      "std_y",      "std_z", "std_roll", "std_pitch", "std_yaw"};
  const std::vector<std::string> required(columns.begin() + 3, columns.end());
  std::vector<std::string> required_with_time = {"time"};
  required_with_time.insert(required_with_time.end(), required.begin(),
                            required.end());
  const CsvTable table = CsvTable::Read(path, columns, required_with_time);
  if (table.NumRows() == 0) {
    throw ErrorAt(path.string(), ": no navigation rows");
  }
  const bool has_names = table.HasColumn("image_name");
  const bool has_dives = table.HasColumn("dive");
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
    for (int k = 0; k < 3; ++k) {
      record.position(k) = table.Double(row, columns[3 + k]);
      record.rpy_rad(k) = table.Double(row, columns[6 + k]) * kDegToRad;
      record.position_sigma(k) = table.NonNegativeDouble(row, columns[9 + k]);
      record.rpy_sigma_rad(k) =
          table.NonNegativeDouble(row, columns[12 + k]) * kDegToRad;
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
