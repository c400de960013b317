#include "experiments/views_experiment_io.h"

#include <cmath>
#include <sstream>

#include <fmt/format.h>

#include "common/util/error.h"

namespace uw {
namespace {

double ParseNoiseNumber(const std::string& text) {
  try {
    size_t used = 0;
    const double value = std::stod(text, &used);
    if (used == text.size()) return value;
  } catch (...) {
  }
  throw ErrorAt("--noise: '", text, "' is not a number");
}

}  // namespace

ShotNoise ParseShotNoise(const std::string& text) {
  std::vector<std::string> parts;
  std::stringstream stream(text);
  for (std::string part; std::getline(stream, part, ':');) {
    parts.push_back(part);
  }
  if (parts.size() < 2 || parts.size() > 4) {
    throw ErrorAt(
        "--noise: expected feature_px:spot_px[:direction_deg"
        "[:origin_m]], got '",
        text, "'");
  }
  ShotNoise noise;
  noise.feature_px = ParseNoiseNumber(parts[0]);
  noise.spot_px = ParseNoiseNumber(parts[1]);
  if (parts.size() > 2) noise.direction_deg = ParseNoiseNumber(parts[2]);
  if (parts.size() > 3) noise.origin_m = ParseNoiseNumber(parts[3]);
  noise.Check();
  return noise;
}

std::string ShotNoiseText(const ShotNoise& noise) {
  std::string text = fmt::format("{}:{}", noise.feature_px, noise.spot_px);
  if (noise.direction_deg != 0.0 || noise.origin_m != 0.0) {
    text += fmt::format(":{}", noise.direction_deg);
  }
  if (noise.origin_m != 0.0) text += fmt::format(":{}", noise.origin_m);
  return text;
}

// The tables write numbers as an ostream does by default (%g): the files
// are what they always were.
std::string AccuracyCsvText(const std::vector<ViewsExperimentRow>& rows) {
  std::ostringstream csv;
  csv << "setup,distance_m,feature_px,spot_px,direction_deg,origin_m,"
         "method,num_views,num_unlocalized,items_n,items_invalid,"
         "items_mean_pct,items_std_pct,items_max_abs_pct,images_n,"
         "images_invalid,images_mean_pct,images_std_pct,"
         "images_max_abs_pct\n";
  for (const ViewsExperimentRow& row : rows) {
    csv << row.setup << "," << row.distance_m << "," << row.noise.feature_px
        << "," << row.noise.spot_px << "," << row.noise.direction_deg << ","
        << row.noise.origin_m << "," << ScaleMethodName(row.method) << ","
        << row.num_views << "," << row.num_unlocalized;
    for (const ErrorStats* stats : {&row.items, &row.images}) {
      csv << "," << stats->count << "," << stats->num_invalid << ","
          << 100.0 * stats->mean << "," << 100.0 * stats->std_dev << ","
          << 100.0 * stats->max_abs;
    }
    csv << "\n";
  }
  return csv.str();
}

std::string ViewsCsvText(const std::vector<ViewsExperimentRow>& rows) {
  std::ostringstream csv;
  csv << "setup,distance_m,feature_px,spot_px,method,pitch_deg,roll_deg,"
         "scale_error_pct\n";
  for (const ViewsExperimentRow& row : rows) {
    for (const auto& [pitch, roll, error] : row.image_errors) {
      csv << row.setup << "," << row.distance_m << "," << row.noise.feature_px
          << "," << row.noise.spot_px << "," << ScaleMethodName(row.method)
          << "," << pitch << "," << roll << ",";
      if (!std::isnan(error)) csv << 100.0 * error;
      csv << "\n";
    }
  }
  return csv.str();
}

}  // namespace uw
