#include "calib/board.h"

#include <gtest/gtest.h>

#include "common/util/error.h"

namespace uw {
namespace {

TEST(ParseBoard, ChessboardCornersAreMrcalsGrid) {
  const CalibrationBoard board = ParseBoard("chessboard:9x6:0.025");
  EXPECT_EQ(board.grid_width, 9);
  EXPECT_EQ(board.grid_height, 6);
  EXPECT_DOUBLE_EQ(board.spacing_m, 0.025);
  const std::vector<Eigen::Vector3d> corners = board.CornersInBoard();
  ASSERT_EQ(corners.size(), 54u);
  // Row-major, x fastest: corner 10 is (1, 1).
  EXPECT_TRUE(corners[10].isApprox(Eigen::Vector3d(0.025, 0.025, 0.0)));
  EXPECT_TRUE(corners[53].isApprox(Eigen::Vector3d(0.2, 0.125, 0.0)));
  EXPECT_EQ(ParseBoard(board.ToString()).spacing_m, board.spacing_m);
  EXPECT_EQ(board.ToString(), "chessboard:9x6:0.025");
}

TEST(ParseBoard, AprilGridCornersAreKalibrs) {
  const CalibrationBoard board = ParseBoard("aprilgrid:6x6:0.088:0.3");
  EXPECT_EQ(board.kind, BoardKind::kAprilGrid);
  EXPECT_FALSE(board.IsRegularGrid());
  EXPECT_EQ(board.grid_width, 12);
  EXPECT_EQ(board.grid_height, 12);
  const std::vector<Eigen::Vector3d> corners = board.CornersInBoard();
  // Tag 0's corners 0, 1, 13, 12 (lower left, lower right, upper right,
  // upper left), tag 1 one pitch (1.3 tag sides) to the right.
  EXPECT_TRUE(corners[1].isApprox(Eigen::Vector3d(0.088, 0.0, 0.0)));
  EXPECT_TRUE(corners[13].isApprox(Eigen::Vector3d(0.088, 0.088, 0.0)));
  EXPECT_TRUE(corners[2].isApprox(Eigen::Vector3d(1.3 * 0.088, 0.0, 0.0)));
  EXPECT_TRUE(corners[143].isApprox(
      Eigen::Vector3d(5 * 1.3 * 0.088 + 0.088, 5 * 1.3 * 0.088 + 0.088, 0)));
  EXPECT_EQ(ParseBoard(board.ToString()).tag_gap, 0.3);
}

TEST(ParseBoard, CharucoCornersAreItsInnerChessboardCorners) {
  const CalibrationBoard board =
      ParseBoard("charuco:20x16:0.004:0.0032:DICT_4X4_1000:legacy");
  EXPECT_EQ(board.kind, BoardKind::kCharuco);
  EXPECT_TRUE(board.IsRegularGrid());
  EXPECT_EQ(board.grid_width, 19);
  EXPECT_EQ(board.grid_height, 15);
  EXPECT_EQ(board.dictionary, "DICT_4X4_1000");
  EXPECT_TRUE(board.legacy);
  EXPECT_TRUE(
      board.CornersInBoard()[20].isApprox(Eigen::Vector3d(0.004, 0.004, 0.0)));
  EXPECT_EQ(board.ToString(),
            "charuco:20x16:0.004:0.0032:DICT_4X4_1000:legacy");
  EXPECT_FALSE(ParseBoard("charuco:5x5:0.04:0.03:DICT_6X6_250").legacy);
  // Markers larger than squares, a dictionary too small for the board, an
  // unknown dictionary, a misspelt flag.
  EXPECT_THROW(ParseBoard("charuco:5x5:0.04:0.05:DICT_6X6_250"), Error);
  EXPECT_THROW(ParseBoard("charuco:20x20:0.04:0.03:DICT_4X4_50"), Error);
  EXPECT_THROW(ParseBoard("charuco:5x5:0.04:0.03:DICT_9X9_50"), Error);
  EXPECT_THROW(ParseBoard("charuco:5x5:0.04:0.03:DICT_6X6_250:old"), Error);
  EXPECT_THROW(ParseBoard("charuco:5x5:0.04:0.03"), Error);
}

TEST(MrcalLattice, PutsAprilGridCornersOnAnEvenLattice) {
  const CalibrationBoard grid = ParseBoard("aprilgrid:6x6:0.088:0.3");
  const BoardLattice lattice = MrcalLattice(grid);
  EXPECT_EQ(lattice.regular.grid_width, 76);
  EXPECT_EQ(lattice.regular.grid_height, 76);
  EXPECT_NEAR(lattice.regular.spacing_m, 0.0088, 1e-15);
  const std::vector<Eigen::Vector3d> corners = grid.CornersInBoard();
  const std::vector<Eigen::Vector3d> points = lattice.regular.CornersInBoard();
  for (size_t k = 0; k < corners.size(); ++k) {
    EXPECT_LT((points[lattice.point_of_corner[k]] - corners[k]).norm(), 1e-12)
        << k;
  }
  // A chessboard is its own lattice.
  const CalibrationBoard chessboard = ParseBoard("chessboard:9x6:0.025");
  EXPECT_EQ(MrcalLattice(chessboard).regular.NumCorners(), 54);
  EXPECT_EQ(MrcalLattice(chessboard).point_of_corner[53], 53);
  EXPECT_THROW(MrcalLattice(ParseBoard("aprilgrid:6x6:0.088:0.3183")), Error);
}

TEST(ParseBoard, RejectsMalformedSpecsSayingWhatIsExpected) {
  for (const char* spec :
       {"", "chessboard", "chessboard:9x6", "chessboard:9:0.02",
        "chessboard:9x6:0", "chessboard:9x6:-1", "chessboard:9x6:abc",
        "chessboard:1x6:0.02", "chessboard:9.5x6:0.02", "chessboard:9x6:nan",
        "chessboard:9x6:0.02:1", "checkerboard:9x6:0.02", "aprilgrid:6x6:0.088",
        "aprilgrid:6x6:0.088:1.5", "aprilgrid:6x6:0.088:0"}) {
    try {
      ParseBoard(spec);
      ADD_FAILURE() << "accepted '" << spec << "'";
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what()).find("--board"), std::string::npos)
          << error.what();
    }
  }
}

}  // namespace
}  // namespace uw
