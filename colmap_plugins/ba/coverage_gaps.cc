#include "colmap_plugins/ba/coverage_gaps.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

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
  Eigen::AlignedBox2d box;
  for (const Eigen::Vector2d& point : points) box.extend(point);
  const double area = std::max(box.sizes().prod(), 1e-12);
  gaps.cell_size = options.cell_factor *
                   std::sqrt(area / static_cast<double>(points.size()));
  const int nx = static_cast<int>(box.sizes().x() / gaps.cell_size) + 1;
  const int ny = static_cast<int>(box.sizes().y() / gaps.cell_size) + 1;
  std::vector<char> occupied(static_cast<size_t>(nx) * ny, 0);
  const auto at = [&](int x, int y) -> char& {
    return occupied[static_cast<size_t>(y) * nx + x];
  };
  for (const Eigen::Vector2d& point : points) {
    const Eigen::Vector2d cell = (point - box.min()) / gaps.cell_size;
    at(std::min(nx - 1, static_cast<int>(cell.x())),
       std::min(ny - 1, static_cast<int>(cell.y()))) = 1;
  }
  // Is there an occupied cell from (x, y) in direction (dx, dy), within
  // max_gap_cells?
  const auto reaches = [&](int x, int y, int dx, int dy) {
    for (int k = 1; k <= options.max_gap_cells; ++k) {
      const int cx = x + k * dx;
      const int cy = y + k * dy;
      if (cx < 0 || cy < 0 || cx >= nx || cy >= ny) return false;
      if (at(cx, cy)) return true;
    }
    return false;
  };
  std::vector<char> candidate(occupied.size(), 0);
  for (int y = 0; y < ny; ++y) {
    for (int x = 0; x < nx; ++x) {
      candidate[static_cast<size_t>(y) * nx + x] =
          !at(x, y) && reaches(x, y, -1, 0) && reaches(x, y, 1, 0) &&
          reaches(x, y, 0, -1) && reaches(x, y, 0, 1);
    }
  }
  // Components of candidate cells (side by side); the large enough ones.
  std::vector<char> visited(occupied.size(), 0);
  for (size_t start = 0; start < candidate.size(); ++start) {
    if (!candidate[start] || visited[start]) continue;
    std::vector<size_t> component = {start};
    visited[start] = 1;
    for (size_t k = 0; k < component.size(); ++k) {
      const int x = static_cast<int>(component[k] % nx);
      const int y = static_cast<int>(component[k] / nx);
      const int neighbours[4][2] = {
          {x - 1, y}, {x + 1, y}, {x, y - 1}, {x, y + 1}};
      for (const auto& [cx, cy] : neighbours) {
        if (cx < 0 || cy < 0 || cx >= nx || cy >= ny) continue;
        const size_t index = static_cast<size_t>(cy) * nx + cx;
        if (candidate[index] && !visited[index]) {
          visited[index] = 1;
          component.push_back(index);
        }
      }
    }
    if (static_cast<int>(component.size()) < options.min_cells) continue;
    std::sort(component.begin(), component.end());
    for (const size_t index : component) {
      gaps.cell_centres.push_back(
          box.min() +
          gaps.cell_size *
              Eigen::Vector2d(static_cast<double>(index % nx) + 0.5,
                              static_cast<double>(index / nx) + 0.5));
    }
  }
  return gaps;
}

}  // namespace uw
