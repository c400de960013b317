#include "calib/image_dives.h"

#include "common/util/csv.h"
#include "common/util/error.h"

namespace uw {

std::map<std::string, int> ReadImageDives(const std::string& path) {
  std::map<std::string, int> dives;
  if (path.empty()) return dives;
  const CsvTable table =
      CsvTable::Read(path, {"image_name", "dive"}, {"image_name", "dive"});
  for (size_t row = 0; row < table.NumRows(); ++row) {
    if (!dives.emplace(table.Text(row, "image_name"), table.Int(row, "dive", 1))
             .second) {
      throw ErrorAt(table.Where(row), ": image ", table.Text(row, "image_name"),
                    " is listed twice");
    }
  }
  return dives;
}

}  // namespace uw
