#include "colmap_plugins/nav/image_times.h"

#include <unordered_map>

#include "common/util/csv.h"
#include "common/util/error.h"

namespace uw {

std::vector<ImageTime> ReadImageTimesCsv(
    const std::filesystem::path& path, std::optional<int> time_zone_offset_s) {
  const CsvTable table = CsvTable::Read(path, {"image_name", "time", "dive"},
                                        {"image_name", "time"});
  if (table.NumRows() == 0) throw ErrorAt(path.string(), ": no image rows");
  const bool has_dives = table.HasColumn("dive");
  std::vector<ImageTime> times;
  std::unordered_map<std::string, int> line_of_image;
  for (size_t row = 0; row < table.NumRows(); ++row) {
    ImageTime time;
    time.line = table.Line(row);
    time.image_name = table.Text(row, "image_name");
    if (time.image_name.empty()) {
      throw ErrorAt(table.Where(row), ": empty image_name");
    }
    time.time_s = table.Time(row, "time", time_zone_offset_s);
    if (has_dives) time.dive = table.Int(row, "dive", 1);
    const auto [previous, inserted] =
        line_of_image.emplace(time.image_name, time.line);
    if (!inserted) {
      throw ErrorAt(table.Where(row), ": image '", time.image_name,
                    "' already has a row at line ", previous->second);
    }
    times.push_back(time);
  }
  return times;
}

}  // namespace uw
