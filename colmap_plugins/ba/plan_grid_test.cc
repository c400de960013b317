#include "colmap_plugins/ba/plan_grid.h"

#include <gtest/gtest.h>

namespace uw {
namespace {

// 100 points on a 10 m x 4 m grid: mean spacing 0.632 m, cells of 2x that.
std::vector<Eigen::Vector2d> GridPoints() {
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i < 25; ++i) {
    for (int j = 0; j < 4; ++j) {
      points.emplace_back(10.0 * i / 24.0, 4.0 * j / 3.0);
    }
  }
  return points;
}

TEST(PlanGrid, CellsFollowTheMeanSpacing) {
  const PlanGrid grid(GridPoints(), 2.0);
  EXPECT_NEAR(grid.CellSize(), 2.0 * std::sqrt(40.0 / 100.0), 1e-12);
  EXPECT_EQ(grid.Width(), static_cast<int>(10.0 / grid.CellSize()) + 1);
  EXPECT_EQ(grid.Height(), static_cast<int>(4.0 / grid.CellSize()) + 1);
  // The far corner goes to the last cell, the origin to the first.
  EXPECT_EQ(grid.IndexOf({0.0, 0.0}), 0u);
  EXPECT_EQ(grid.IndexOf({10.0, 4.0}), grid.NumCells() - 1);
  EXPECT_TRUE(grid.Centre(0).isApprox(
      Eigen::Vector2d::Constant(0.5 * grid.CellSize())));
}

TEST(PlanGrid, ComponentsAreSideBySideOrAlsoDiagonal) {
  const PlanGrid grid(GridPoints(), 2.0);
  ASSERT_GE(grid.Width(), 6);
  ASSERT_GE(grid.Height(), 3);
  std::vector<char> marked(grid.NumCells(), 0);
  // A diagonal pair, and a horizontal pair apart from it.
  marked[grid.Index(0, 0)] = 1;
  marked[grid.Index(1, 1)] = 1;
  marked[grid.Index(5, 2)] = 1;
  marked[grid.Index(4, 2)] = 1;
  const auto four = grid.Components(marked, false, 1);
  ASSERT_EQ(four.size(), 3u);
  EXPECT_EQ(four[0], std::vector<size_t>{grid.Index(0, 0)});
  EXPECT_EQ(four[2], (std::vector<size_t>{grid.Index(4, 2), grid.Index(5, 2)}));
  EXPECT_EQ(grid.Components(marked, false, 2).size(), 1u);
  const auto eight = grid.Components(marked, true, 2);
  ASSERT_EQ(eight.size(), 2u);
  EXPECT_EQ(eight[0],
            (std::vector<size_t>{grid.Index(0, 0), grid.Index(1, 1)}));
}

}  // namespace
}  // namespace uw
