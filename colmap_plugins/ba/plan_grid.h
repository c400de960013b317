// A plan-view grid over a model's points, in cells of a multiple of their
// mean spacing, and the connected groups of marked cells: what the
// uncertainty map's flags (coverage_gaps.h, short_baselines.h) are found
// on.
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Geometry>

namespace uw {

class PlanGrid {
 public:
  // Cells of cell_factor x sqrt(bounding area / count) over the points'
  // bounding box; `points` must not be empty.
  PlanGrid(const std::vector<Eigen::Vector2d>& points, double cell_factor);

  double CellSize() const { return cell_size_; }
  int Width() const { return nx_; }
  int Height() const { return ny_; }
  size_t NumCells() const { return static_cast<size_t>(nx_) * ny_; }
  size_t Index(int x, int y) const { return static_cast<size_t>(y) * nx_ + x; }
  // The cell of a point (points on the box's far edges go to the last one).
  size_t IndexOf(const Eigen::Vector2d& point) const;
  Eigen::Vector2d Centre(size_t index) const;

  // The groups of marked cells connected side by side (and corner to corner
  // when eight_connected) with at least min_cells cells, each sorted by
  // index, in order of their smallest index.
  std::vector<std::vector<size_t>> Components(const std::vector<char>& marked,
                                              bool eight_connected,
                                              int min_cells) const;

 private:
  Eigen::AlignedBox2d box_;
  double cell_size_ = 0.0;
  int nx_ = 0;
  int ny_ = 0;
};

}  // namespace uw
