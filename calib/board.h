// Calibration boards: what `uwcalib --board` describes, and where its
// corners are on the board.
//
// Corners are numbered as mrcal numbers them (corners.vnl, mrcal's
// calibration object): a grid of grid_width x grid_height points, row-major
// with x fastest; point (i, j) lies at (i, j) * spacing on the board plane
// z = 0. Metres.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace uw {

enum class BoardKind {
  // A chessboard, counted by its inner corners (OpenCV's patternSize).
  kChessboard,
  // Kalibr's AprilGrid: cols x rows tag36h11 tags (2-cell black border) of
  // side spacing_m, tag_gap x spacing_m apart; tag t in row t / cols from
  // the bottom, column t % cols. Its corners are each tag's four, a
  // (2 cols) x (2 rows) grid in Kalibr's order: not evenly spaced.
  kAprilGrid,
  // OpenCV's ChArUco board: cols x rows squares (spacing_m), an ArUco marker
  // (marker_m, of `dictionary`) in every white square; its corners are the
  // (cols - 1) x (rows - 1) inner chessboard corners, evenly spaced, row by
  // row from the top left. Markers fill the white squares row by row from
  // the top, ids counting up. OpenCV >= 4.6 puts a black square at the top
  // left; "legacy" boards (OpenCV < 4.6, and setLegacyPattern) differ from
  // it for an even number of rows: the square at the bottom left is black.
  kCharuco,
};

struct CalibrationBoard {
  BoardKind kind = BoardKind::kChessboard;
  int grid_width = 0;      // corners per row
  int grid_height = 0;     // rows of corners
  double spacing_m = 0.0;  // square side; an AprilGrid's tag side
  double tag_gap = 0.0;    // AprilGrid: gap between tags / tag side
  double marker_m = 0.0;   // ChArUco: marker side
  std::string dictionary;  // ChArUco: OpenCV's name, e.g. DICT_4X4_1000
  bool legacy = false;     // ChArUco: the pre-4.6 layout

  // Corners evenly spaced by spacing_m (what mrcal's board model is).
  bool IsRegularGrid() const { return kind != BoardKind::kAprilGrid; }

  int NumCorners() const { return grid_width * grid_height; }

  // Corner positions on the board, mrcal's order.
  std::vector<Eigen::Vector3d> CornersInBoard() const;

  // The spec string that ParseBoard reads back, e.g. "chessboard:9x6:0.025",
  // "aprilgrid:6x6:0.088:0.3" or "charuco:20x20:0.004:0.0032:DICT_4X4_1000".
  std::string ToString() const;
};

// mrcal 2.2's board is evenly spaced points. A chessboard is one; an
// AprilGrid's corners all lie on a finer one, of spacing tag side / q for
// the smallest q that makes GAP q whole (0.3: q = 10, a 6x6 grid's corners
// on 76 x 76 points): mrcal is given that lattice, the points that are no
// corner marked missing.
struct BoardLattice {
  CalibrationBoard regular;          // a chessboard of the lattice
  std::vector<int> point_of_corner;  // per corner: its lattice point
};
// Throws uw::Error when GAP needs q > 100 or the lattice more than 400
// points a side.
BoardLattice MrcalLattice(const CalibrationBoard& board);

// An observation of the board's corners as one of its lattice's points
// (the points that are no corner missing).
struct BoardObservation;
BoardObservation OnLattice(const BoardObservation& observation,
                           const BoardLattice& lattice);

// Parses a --board value:
//   chessboard:COLSxROWS:SQUARE_M   inner corners per row x rows, square side
//   aprilgrid:COLSxROWS:TAG_M:GAP   Kalibr's tags per row x rows, tag side,
//                                   gap between tags as a fraction of it
//   charuco:COLSxROWS:SQUARE_M:MARKER_M:DICT[:legacy]
//                                   squares per row x rows, square and
//                                   marker sides, OpenCV's dictionary name
//                                   (DICT_4X4_50 ... DICT_APRILTAG_36h11)
// Throws uw::Error saying what was expected.
CalibrationBoard ParseBoard(const std::string& spec);

// OpenCV's predefined ArUco dictionaries by name, in the order of
// cv::aruco::PREDEFINED_DICTIONARY_NAME (the index is its value); and how
// many markers each holds.
const std::vector<std::pair<std::string, int>>& ArucoDictionaries();

}  // namespace uw
