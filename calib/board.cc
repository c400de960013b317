#include "calib/board.h"

#include <cmath>
#include <sstream>

#include "colmap_plugins/util/error.h"

namespace uw {
namespace {

std::vector<std::string> SplitAt(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream stream(text);
  while (std::getline(stream, part, separator)) parts.push_back(part);
  if (!text.empty() && text.back() == separator) parts.emplace_back();
  return parts;
}

// Parses all of `text` as a number, or throws naming the board spec.
double ParseNumber(const std::string& text, const std::string& spec,
                   const char* what) {
  size_t used = 0;
  double value = 0.0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || !std::isfinite(value)) {
    throw ErrorAt("--board ", spec, ": ", what, " must be a number, got '",
                  text, "'");
  }
  return value;
}

int ParseCount(const std::string& text, const std::string& spec,
               const char* what) {
  const double value = ParseNumber(text, spec, what);
  if (value != std::floor(value) || value < 2 || value > 1000) {
    throw ErrorAt("--board ", spec, ": ", what,
                  " must be a whole number from 2 to 1000, got '", text, "'");
  }
  return static_cast<int>(value);
}

}  // namespace

std::vector<Eigen::Vector3d> CalibrationBoard::CornersInBoard() const {
  std::vector<Eigen::Vector3d> corners;
  corners.reserve(NumCorners());
  for (int j = 0; j < grid_height; ++j) {
    for (int i = 0; i < grid_width; ++i) {
      corners.emplace_back(i * spacing_m, j * spacing_m, 0.0);
    }
  }
  return corners;
}

std::string CalibrationBoard::ToString() const {
  std::ostringstream text;
  text.precision(17);
  text << "chessboard:" << grid_width << "x" << grid_height << ":" << spacing_m;
  return text.str();
}

CalibrationBoard ParseBoard(const std::string& spec) {
  const std::vector<std::string> fields = SplitAt(spec, ':');
  if (fields.empty() || fields[0] != "chessboard") {
    throw ErrorAt("--board ", spec,
                  ": expected chessboard:COLSxROWS:SQUARE_M (inner corners, "
                  "square side in metres), e.g. chessboard:9x6:0.025");
  }
  if (fields.size() != 3) {
    throw ErrorAt("--board ", spec,
                  ": a chessboard is chessboard:COLSxROWS:SQUARE_M, e.g. "
                  "chessboard:9x6:0.025");
  }
  const std::vector<std::string> size = SplitAt(fields[1], 'x');
  if (size.size() != 2) {
    throw ErrorAt("--board ", spec, ": the size must be COLSxROWS, got '",
                  fields[1], "'");
  }
  CalibrationBoard board;
  board.kind = BoardKind::kChessboard;
  board.grid_width = ParseCount(size[0], spec, "COLS (inner corners per row)");
  board.grid_height = ParseCount(size[1], spec, "ROWS (rows of inner corners)");
  board.spacing_m = ParseNumber(fields[2], spec, "SQUARE_M");
  if (board.spacing_m <= 0.0) {
    throw ErrorAt("--board ", spec, ": SQUARE_M must be positive");
  }
  return board;
}

}  // namespace uw
