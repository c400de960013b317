#include "colmap_plugins/ba/coverage_gaps.h"

#include <cmath>

#include "colmap_plugins/ba/plan_grid.h"
#include "common/util/error.h"

namespace uw {

void CoverageGapOptions::Check() const {
  if (!(cell_factor > 0.0) || !std::isfinite(cell_factor)) {
    throw ErrorAt("coverage gaps: cell_factor must be > 0, got ", cell_factor);
  }
  if (min_cells < 1) {
    throw ErrorAt("coverage gaps: min_cells must be >= 1, got ", min_cells);
  }
  if (max_gap_cells < 1) {
    throw ErrorAt("coverage gaps: max_gap_cells must be >= 1, got ",
                  max_gap_cells);
  }
}

CoverageGaps FindCoverageGaps(const std::vector<Eigen::Vector2d>& points,
                              const CoverageGapOptions& options) {
  options.Check();
  CoverageGaps gaps;
  if (points.size() < 10) return gaps;
  const PlanGrid grid(points, options.cell_factor);
  gaps.cell_size = grid.CellSize();
  const int nx = grid.Width();
  const int ny = grid.Height();
  std::vector<char> occupied(grid.NumCells(), 0);
  for (const Eigen::Vector2d& point : points) occupied[grid.IndexOf(point)] = 1;
  // Is there an occupied cell from (x, y) in direction (dx, dy), within
  // max_gap_cells?
  const auto reaches = [&](int x, int y, int dx, int dy) {
    for (int k = 1; k <= options.max_gap_cells; ++k) {
      const int cx = x + k * dx;
      const int cy = y + k * dy;
      if (cx < 0 || cy < 0 || cx >= nx || cy >= ny) return false;
      if (occupied[grid.Index(cx, cy)]) return true;
    }
    return false;
  };
  std::vector<char> candidate(occupied.size(), 0);
  for (int y = 0; y < ny; ++y) {
    for (int x = 0; x < nx; ++x) {
      candidate[grid.Index(x, y)] =
          !occupied[grid.Index(x, y)] && reaches(x, y, -1, 0) &&
          reaches(x, y, 1, 0) && reaches(x, y, 0, -1) && reaches(x, y, 0, 1);
    }
  }
  // Gaps: candidate cells side by side, the large enough groups.
  for (const std::vector<size_t>& component :
       grid.Components(candidate, false, options.min_cells)) {
    for (const size_t index : component) {
      gaps.cell_centres.push_back(grid.Centre(index));
    }
  }
  return gaps;
}

}  // namespace uw
