#include "calib/corners_vnl.h"

#include <cmath>
#include <map>
#include <sstream>

#include <fmt/format.h>

#include "common/util/error.h"
#include "common/util/file.h"

namespace uw {
namespace {

constexpr const char* kMissing = "-";

bool HasWhiteSpace(const std::string& text) {
  return text.find_first_of(" \t\r\n") != std::string::npos;
}

// The level of a weight 2^-level, or -1 if it is not a power of 1/2.
int LevelOfWeight(double weight) {
  for (int level = 0; level < 31; ++level) {
    if (weight == std::ldexp(1.0, -level)) return level;
  }
  return -1;
}

// A field that must be a finite number, or "-".
bool ParseField(const std::string& field, double* value) {
  if (field == kMissing) return false;
  size_t used = 0;
  try {
    *value = std::stod(field, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != field.size() || !std::isfinite(*value)) {
    throw Error("'" + field + "' is neither a finite number nor '-'");
  }
  return true;
}

}  // namespace

int BoardObservation::NumFoundCorners() const {
  int found = 0;
  for (const double weight : weights) found += weight > 0.0;
  return found;
}

std::string FormatCornersVnl(const std::vector<BoardObservation>& observations,
                             CornerWeightColumn column,
                             const std::vector<std::string>& comments) {
  std::ostringstream text;
  for (const std::string& comment : comments) text << "## " << comment << "\n";
  text << (column == CornerWeightColumn::kLevel ? "# filename x y level\n"
                                                : "# filename x y weight\n");
  size_t num_corners = 0;
  for (const BoardObservation& observation : observations) {
    const std::string& image = observation.image;
    if (image.empty() || HasWhiteSpace(image)) {
      throw ErrorAt("corners.vnl: image name '", image,
                    "' is empty or has white space (mrcal splits at it)");
    }
    if (!observation.Found()) {
      text << image << " - - -\n";
      continue;
    }
    if (observation.weights.size() != observation.pixels.size() ||
        (num_corners != 0 && observation.pixels.size() != num_corners)) {
      throw ErrorAt("corners.vnl: ", image, ": ", observation.pixels.size(),
                    " corners and ", observation.weights.size(),
                    " weights; every image needs the board's ", num_corners);
    }
    num_corners = observation.pixels.size();
    for (size_t k = 0; k < num_corners; ++k) {
      const Eigen::Vector2d& pixel = observation.pixels[k];
      const double weight = observation.weights[k];
      if (!std::isfinite(weight) || (weight > 0.0 && !pixel.allFinite())) {
        throw ErrorAt("corners.vnl: ", image, ": corner ", k, " is not finite");
      }
      if (weight <= 0.0) {
        text << image << " - - -\n";
        continue;
      }
      text << image << " "
           << fmt::format("{:.6f} {:.6f} ", pixel.x(), pixel.y());
      if (column == CornerWeightColumn::kLevel) {
        const int level = LevelOfWeight(weight);
        if (level < 0) {
          throw ErrorAt("corners.vnl: ", image, ": corner ", k, "'s weight ",
                        weight, " is no level (2^-level); write weights");
        }
        text << level << "\n";
      } else {
        text << fmt::format("{:.9g}\n", weight);
      }
    }
  }
  return text.str();
}

CornersVnl ParseCornersVnl(const std::string& text, const std::string& where,
                           int num_corners) {
  CornersVnl result;
  std::vector<int> first_lines;  // of each observation's block
  std::map<std::string, int> first_line_of_image;
  std::istringstream lines(text);
  std::string line;
  int line_number = 0;
  while (std::getline(lines, line)) {
    ++line_number;
    const size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos) continue;
    std::istringstream row(line.substr(first + (line[first] == '#')));
    std::vector<std::string> fields;
    std::string field;
    while (row >> field) fields.push_back(field);
    if (line[first] == '#') {
      // The legend, "# filename x y level|weight", says what the fourth
      // column holds; other comments are skipped, as mrcal does.
      if (fields.size() == 4 && fields[0] == "filename") {
        if (fields[3] != "level" && fields[3] != "weight") {
          throw ErrorAt(where, ":", line_number,
                        ": the fourth column must be 'level' or 'weight', "
                        "got '",
                        fields[3], "'");
        }
        result.column = fields[3] == "weight" ? CornerWeightColumn::kWeight
                                              : CornerWeightColumn::kLevel;
      }
      continue;
    }
    if (fields.size() != 3 && fields.size() != 4) {
      throw ErrorAt(where, ":", line_number,
                    ": expected 'filename x y [level|weight]', got ",
                    fields.size(), " fields");
    }
    const std::string& image = fields[0];
    if (result.observations.empty() ||
        result.observations.back().image != image) {
      const auto [it, inserted] =
          first_line_of_image.emplace(image, line_number);
      if (!inserted) {
        throw ErrorAt(where, ":", line_number, ": image ", image,
                      " appears again (first at line ", it->second,
                      "); an image's rows must be one block");
      }
      result.observations.push_back({image, {}, {}});
      first_lines.push_back(line_number);
    }
    Eigen::Vector2d pixel(0.0, 0.0);
    double weight = 1.0;
    bool found = true;
    try {
      found = ParseField(fields[1], &pixel.x());
      found = ParseField(fields[2], &pixel.y()) && found;
      double value = 0.0;
      if (fields.size() == 4 &&
          (!ParseField(fields[3], &value) || value < 0.0)) {
        found = false;
      } else if (fields.size() == 4 &&
                 result.column == CornerWeightColumn::kLevel) {
        if (value != std::floor(value) || value > 30) {
          throw Error("level '" + fields[3] + "' is not a whole number");
        }
        weight = std::ldexp(1.0, -static_cast<int>(value));
      } else if (fields.size() == 4) {
        weight = value;
      }
    } catch (const Error& error) {
      throw ErrorAt(where, ":", line_number, ": image ", image, ": ",
                    error.what());
    }
    // mrcal: negative coordinates or a zero weight also mark a missing
    // corner.
    if (!found || weight <= 0.0 || pixel.x() < 0.0 || pixel.y() < 0.0) {
      pixel.setZero();
      weight = -1.0;
    }
    result.observations.back().pixels.push_back(pixel);
    result.observations.back().weights.push_back(weight);
  }
  for (size_t i = 0; i < result.observations.size(); ++i) {
    BoardObservation& observation = result.observations[i];
    const int rows = static_cast<int>(observation.pixels.size());
    if (observation.NumFoundCorners() == 0 &&
        (rows == 1 || rows == num_corners)) {
      observation.pixels.clear();  // no board in this image
      observation.weights.clear();
      continue;
    }
    if (num_corners == 0) num_corners = rows;
    if (rows != num_corners) {
      throw ErrorAt(where, ":", first_lines[i], ": image ", observation.image,
                    " has ", rows, " rows; a board has ", num_corners,
                    " corners (write one row 'NAME - - -' for no board)");
    }
  }
  return result;
}

CornersVnl ReadCornersVnl(const std::string& path, int num_corners) {
  return ParseCornersVnl(ReadFileToString(path), path, num_corners);
}

}  // namespace uw
