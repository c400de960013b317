#include "colmap_plugins/ba/coverage_gaps.h"

#include <random>

#include <gtest/gtest.h>

#include "common/util/error.h"

namespace uw {
namespace {

// Points uniform over a 12 m x 6 m survey, 40 per m^2, leaving out those
// `keep` refuses.
template <typename Keep>
std::vector<Eigen::Vector2d> Survey(const Keep& keep) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> x(0.0, 12.0);
  std::uniform_real_distribution<double> y(0.0, 6.0);
  std::vector<Eigen::Vector2d> points;
  for (int k = 0; k < 12 * 6 * 40; ++k) {
    const Eigen::Vector2d point(x(rng), y(rng));
    if (keep(point)) points.push_back(point);
  }
  return points;
}

TEST(CoverageGaps, AHoleInsideTheSurveyIsAGapAndOnlyThere) {
  const auto outside_hole = [](const Eigen::Vector2d& p) {
    return !(p.x() > 5.0 && p.x() < 7.0 && p.y() > 2.0 && p.y() < 4.0);
  };
  const CoverageGaps gaps =
      FindCoverageGaps(Survey(outside_hole), CoverageGapOptions());
  EXPECT_GT(gaps.cell_size, 0.4);
  EXPECT_LT(gaps.cell_size, 0.8);
  ASSERT_FALSE(gaps.cell_centres.empty());
  for (const Eigen::Vector2d& centre : gaps.cell_centres) {
    EXPECT_GT(centre.x(), 5.0 - gaps.cell_size) << centre.transpose();
    EXPECT_LT(centre.x(), 7.0 + gaps.cell_size) << centre.transpose();
    EXPECT_GT(centre.y(), 2.0 - gaps.cell_size) << centre.transpose();
    EXPECT_LT(centre.y(), 4.0 + gaps.cell_size) << centre.transpose();
  }
  // Most of the hole's 4 m^2 is found.
  EXPECT_GT(gaps.Area(), 2.0);
  EXPECT_LT(gaps.Area(), 6.0);
}

TEST(CoverageGaps, EdgesAndTheInnerCornerOfAnLAreNotGaps) {
  const auto everywhere = [](const Eigen::Vector2d&) { return true; };
  EXPECT_TRUE(FindCoverageGaps(Survey(everywhere), CoverageGapOptions())
                  .cell_centres.empty());
  const auto l_shape = [](const Eigen::Vector2d& p) {
    return p.x() < 4.0 || p.y() < 2.0;
  };
  EXPECT_TRUE(FindCoverageGaps(Survey(l_shape), CoverageGapOptions())
                  .cell_centres.empty());
  EXPECT_TRUE(FindCoverageGaps({}, CoverageGapOptions()).cell_centres.empty());
  // A hole of one cell (0.63 m here, cell 8 x 3 of the grid) is a notch,
  // not a gap; with min_cells 1 it is one.
  const auto small_hole = [](const Eigen::Vector2d& p) {
    return !(p.x() > 4.95 && p.x() < 5.8 && p.y() > 1.8 && p.y() < 2.6);
  };
  EXPECT_TRUE(FindCoverageGaps(Survey(small_hole), CoverageGapOptions())
                  .cell_centres.empty());
  CoverageGapOptions single;
  single.min_cells = 1;
  EXPECT_FALSE(
      FindCoverageGaps(Survey(small_hole), single).cell_centres.empty());
  CoverageGapOptions bad;
  bad.cell_factor = 0.0;
  EXPECT_THROW(bad.Check(), Error);
}

}  // namespace
}  // namespace uw
