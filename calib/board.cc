#include "calib/board.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include <fmt/format.h>

#include "calib/corners_vnl.h"
#include "common/util/error.h"
#include "common/util/number_text.h"

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
  const std::optional<double> value = FiniteDouble(text);
  if (!value) {
    throw ErrorAt("--board ", spec, ": ", what, " must be a number, got '",
                  text, "'");
  }
  return *value;
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

// The shortest text that reads back as `value` (0.025, not
// 0.025000000000000001).
std::string ShortestText(double value) {
  std::string text;
  for (int precision = 6; precision <= 17; ++precision) {
    text = fmt::format("{:.{}g}", value, precision);
    if (std::strtod(text.c_str(), nullptr) == value) break;
  }
  return text;
}

}  // namespace

std::vector<Eigen::Vector3d> CalibrationBoard::CornersInBoard() const {
  std::vector<Eigen::Vector3d> corners;
  corners.reserve(NumCorners());
  // Kalibr: corner c of a row lies at (c / 2) tag pitches plus one tag
  // side for the tag's right (upper) corners.
  const auto position = [&](int c) {
    if (kind != BoardKind::kAprilGrid) return c * spacing_m;
    return (c / 2) * (1.0 + tag_gap) * spacing_m + (c % 2) * spacing_m;
  };
  for (int j = 0; j < grid_height; ++j) {
    for (int i = 0; i < grid_width; ++i) {
      corners.emplace_back(position(i), position(j), 0.0);
    }
  }
  return corners;
}

std::string CalibrationBoard::ToString() const {
  std::ostringstream text;
  if (kind == BoardKind::kAprilGrid) {
    text << "aprilgrid:" << grid_width / 2 << "x" << grid_height / 2 << ":"
         << ShortestText(spacing_m) << ":" << ShortestText(tag_gap);
  } else if (kind == BoardKind::kCharuco) {
    text << "charuco:" << grid_width + 1 << "x" << grid_height + 1 << ":"
         << ShortestText(spacing_m) << ":" << ShortestText(marker_m) << ":"
         << dictionary << (legacy ? ":legacy" : "");
  } else {
    text << "chessboard:" << grid_width << "x" << grid_height << ":"
         << ShortestText(spacing_m);
  }
  return text.str();
}

BoardLattice MrcalLattice(const CalibrationBoard& board) {
  BoardLattice lattice;
  lattice.regular = board;
  const int num_corners = board.NumCorners();
  if (board.IsRegularGrid()) {
    for (int k = 0; k < num_corners; ++k) lattice.point_of_corner.push_back(k);
    return lattice;
  }
  int q = 1;
  while (q <= 100 && std::abs(board.tag_gap * q -
                              std::round(board.tag_gap * q)) > 1e-9 * q) {
    ++q;
  }
  if (q > 100) {
    throw ErrorAt(board.ToString(), ": GAP ", board.tag_gap,
                  " is no fraction p/q with q <= 100; mrcal cannot place "
                  "the corners on an even lattice");
  }
  const int pitch = q + static_cast<int>(std::lround(board.tag_gap * q));
  const auto position = [&](int c) { return (c / 2) * pitch + (c % 2) * q; };
  const int width = position(board.grid_width - 1) + 1;
  const int height = position(board.grid_height - 1) + 1;
  if (width > 400 || height > 400) {
    throw ErrorAt(board.ToString(), ": its corners need a ", width, " x ",
                  height, " lattice for mrcal; at most 400 a side");
  }
  lattice.regular.kind = BoardKind::kChessboard;
  lattice.regular.grid_width = width;
  lattice.regular.grid_height = height;
  lattice.regular.spacing_m = board.spacing_m / q;
  lattice.regular.tag_gap = 0.0;
  for (int k = 0; k < num_corners; ++k) {
    const int i = k % board.grid_width;
    const int j = k / board.grid_width;
    lattice.point_of_corner.push_back(position(j) * width + position(i));
  }
  return lattice;
}

BoardObservation OnLattice(const BoardObservation& observation,
                           const BoardLattice& lattice) {
  if (observation.pixels.size() != lattice.point_of_corner.size() ||
      observation.weights.size() != lattice.point_of_corner.size()) {
    throw ErrorAt(observation.image, ": ", observation.pixels.size(),
                  " corners, but the board has ",
                  lattice.point_of_corner.size());
  }
  const int num_points = lattice.regular.NumCorners();
  BoardObservation on_lattice;
  on_lattice.image = observation.image;
  on_lattice.pixels.assign(num_points, Eigen::Vector2d::Zero());
  on_lattice.weights.assign(num_points, -1.0);
  for (size_t k = 0; k < lattice.point_of_corner.size(); ++k) {
    on_lattice.pixels[lattice.point_of_corner[k]] = observation.pixels[k];
    on_lattice.weights[lattice.point_of_corner[k]] = observation.weights[k];
  }
  return on_lattice;
}

const std::vector<std::pair<std::string, int>>& ArucoDictionaries() {
  static const std::vector<std::pair<std::string, int>> kDictionaries = {
      {"DICT_4X4_50", 50},           {"DICT_4X4_100", 100},
      {"DICT_4X4_250", 250},         {"DICT_4X4_1000", 1000},
      {"DICT_5X5_50", 50},           {"DICT_5X5_100", 100},
      {"DICT_5X5_250", 250},         {"DICT_5X5_1000", 1000},
      {"DICT_6X6_50", 50},           {"DICT_6X6_100", 100},
      {"DICT_6X6_250", 250},         {"DICT_6X6_1000", 1000},
      {"DICT_7X7_50", 50},           {"DICT_7X7_100", 100},
      {"DICT_7X7_250", 250},         {"DICT_7X7_1000", 1000},
      {"DICT_ARUCO_ORIGINAL", 1024}, {"DICT_APRILTAG_16h5", 30},
      {"DICT_APRILTAG_25h9", 35},    {"DICT_APRILTAG_36h10", 2320},
      {"DICT_APRILTAG_36h11", 587}};
  return kDictionaries;
}

CalibrationBoard ParseBoard(const std::string& spec) {
  const std::vector<std::string> fields = SplitAt(spec, ':');
  const char* kExpected =
      ": expected chessboard:COLSxROWS:SQUARE_M (inner corners, square side "
      "in metres; e.g. chessboard:9x6:0.025), aprilgrid:COLSxROWS:TAG_M:GAP "
      "(Kalibr's tags, tag side in metres, gap / tag side; e.g. "
      "aprilgrid:6x6:0.088:0.3) or "
      "charuco:COLSxROWS:SQUARE_M:MARKER_M:DICT[:legacy] (squares, square "
      "and marker sides in metres, OpenCV's dictionary; e.g. "
      "charuco:20x20:0.004:0.0032:DICT_4X4_1000:legacy)";
  const bool chessboard = !fields.empty() && fields[0] == "chessboard";
  const bool aprilgrid = !fields.empty() && fields[0] == "aprilgrid";
  const bool charuco = !fields.empty() && fields[0] == "charuco";
  if ((!chessboard && !aprilgrid && !charuco) ||
      (chessboard && fields.size() != 3) || (aprilgrid && fields.size() != 4) ||
      (charuco && fields.size() != 5 && fields.size() != 6) ||
      (charuco && fields.size() == 6 && fields[5] != "legacy")) {
    throw ErrorAt("--board ", spec, kExpected);
  }
  const std::vector<std::string> size = SplitAt(fields[1], 'x');
  if (size.size() != 2) {
    throw ErrorAt("--board ", spec, ": the size must be COLSxROWS, got '",
                  fields[1], "'");
  }
  CalibrationBoard board;
  board.kind = chessboard  ? BoardKind::kChessboard
               : aprilgrid ? BoardKind::kAprilGrid
                           : BoardKind::kCharuco;
  const int cols = ParseCount(size[0], spec, "COLS");
  const int rows = ParseCount(size[1], spec, "ROWS");
  if (charuco && (cols < 3 || rows < 3)) {
    throw ErrorAt("--board ", spec,
                  ": a ChArUco board needs at least 3x3 squares");
  }
  const int per_cell = aprilgrid ? 2 : 1;  // an AprilGrid's tags: 2x2
  const int inner = charuco ? -1 : 0;      // ChArUco: squares, not corners
  board.grid_width = per_cell * cols + inner;
  board.grid_height = per_cell * rows + inner;
  board.spacing_m =
      ParseNumber(fields[2], spec, aprilgrid ? "TAG_M" : "SQUARE_M");
  if (board.spacing_m <= 0.0) {
    throw ErrorAt("--board ", spec, ": the size in metres must be positive");
  }
  if (aprilgrid) {
    board.tag_gap = ParseNumber(fields[3], spec, "GAP");
    if (board.tag_gap <= 0.0 || board.tag_gap >= 1.0) {
      throw ErrorAt("--board ", spec,
                    ": GAP (between tags, a fraction of the tag side) must "
                    "be in (0, 1)");
    }
  }
  if (charuco) {
    board.marker_m = ParseNumber(fields[3], spec, "MARKER_M");
    if (board.marker_m <= 0.0 || board.marker_m >= board.spacing_m) {
      throw ErrorAt("--board ", spec,
                    ": MARKER_M must be positive and smaller than SQUARE_M");
    }
    board.dictionary = fields[4];
    board.legacy = fields.size() == 6;
    const auto& dictionaries = ArucoDictionaries();
    const auto it = std::find_if(
        dictionaries.begin(), dictionaries.end(),
        [&](const auto& entry) { return entry.first == board.dictionary; });
    if (it == dictionaries.end()) {
      throw ErrorAt("--board ", spec, ": unknown dictionary '",
                    board.dictionary,
                    "'; OpenCV's are DICT_4X4_50 ... DICT_7X7_1000, "
                    "DICT_ARUCO_ORIGINAL and DICT_APRILTAG_16h5/25h9/36h10/"
                    "36h11");
    }
    const int num_markers = (cols * rows) / 2;
    if (num_markers > it->second) {
      throw ErrorAt("--board ", spec, ": ", num_markers, " markers, but ",
                    board.dictionary, " has only ", it->second);
    }
  }
  return board;
}

}  // namespace uw
