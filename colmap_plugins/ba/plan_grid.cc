#include "colmap_plugins/ba/plan_grid.h"

#include <algorithm>
#include <cmath>

namespace uw {

PlanGrid::PlanGrid(const std::vector<Eigen::Vector2d>& points,
                   double cell_factor) {
  for (const Eigen::Vector2d& point : points) box_.extend(point);
  const double area = std::max(box_.sizes().prod(), 1e-12);
  cell_size_ =
      cell_factor * std::sqrt(area / static_cast<double>(points.size()));
  nx_ = static_cast<int>(box_.sizes().x() / cell_size_) + 1;
  ny_ = static_cast<int>(box_.sizes().y() / cell_size_) + 1;
}

size_t PlanGrid::IndexOf(const Eigen::Vector2d& point) const {
  const Eigen::Vector2d cell = (point - box_.min()) / cell_size_;
  return Index(std::clamp(static_cast<int>(cell.x()), 0, nx_ - 1),
               std::clamp(static_cast<int>(cell.y()), 0, ny_ - 1));
}

Eigen::Vector2d PlanGrid::Centre(size_t index) const {
  return box_.min() +
         cell_size_ * Eigen::Vector2d(static_cast<double>(index % nx_) + 0.5,
                                      static_cast<double>(index / nx_) + 0.5);
}

std::vector<std::vector<size_t>> PlanGrid::Components(
    const std::vector<char>& marked, bool eight_connected,
    int min_cells) const {
  std::vector<std::vector<size_t>> components;
  std::vector<char> visited(marked.size(), 0);
  for (size_t start = 0; start < marked.size(); ++start) {
    if (!marked[start] || visited[start]) continue;
    std::vector<size_t> component = {start};
    visited[start] = 1;
    for (size_t k = 0; k < component.size(); ++k) {
      const int x = static_cast<int>(component[k] % nx_);
      const int y = static_cast<int>(component[k] / nx_);
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          if ((dx == 0 && dy == 0) ||
              (!eight_connected && dx != 0 && dy != 0)) {
            continue;
          }
          const int cx = x + dx;
          const int cy = y + dy;
          if (cx < 0 || cy < 0 || cx >= nx_ || cy >= ny_) continue;
          const size_t index = Index(cx, cy);
          if (marked[index] && !visited[index]) {
            visited[index] = 1;
            component.push_back(index);
          }
        }
      }
    }
    if (static_cast<int>(component.size()) < min_cells) continue;
    std::sort(component.begin(), component.end());
    components.push_back(std::move(component));
  }
  return components;
}

}  // namespace uw
