#include "colmap_plugins/ba/short_baselines.h"

#include <algorithm>
#include <cmath>

#include "colmap_plugins/ba/plan_grid.h"
#include "common/util/error.h"

namespace uw {

void ShortBaselineOptions::Check() const {
  if (!(min_angle_deg > 0.0 && min_angle_deg < 90.0)) {
    throw ErrorAt("short baselines: min_angle_deg must be in (0, 90), got ",
                  min_angle_deg);
  }
  if (!(cell_factor > 0.0) || !std::isfinite(cell_factor)) {
    throw ErrorAt("short baselines: cell_factor must be > 0, got ",
                  cell_factor);
  }
  if (min_points_per_cell < 1) {
    throw ErrorAt("short baselines: min_points_per_cell must be >= 1, got ",
                  min_points_per_cell);
  }
  if (min_cells < 1) {
    throw ErrorAt("short baselines: min_cells must be >= 1, got ", min_cells);
  }
}

double TriangulationAngleDeg(const Reconstruction& model,
                             const Point3D& point) {
  std::vector<Eigen::Vector3d> rays;
  for (const TrackElement& element : point.track) {
    const Image* image = model.FindImage(element.image_id);
    if (image == nullptr) continue;
    const Eigen::Vector3d ray = image->ProjectionCenter() - point.xyz;
    if (ray.norm() > 0.0) rays.push_back(ray.normalized());
  }
  // The smallest cosine over pairs; a track is a few dozen images at most.
  double min_cosine = 1.0;
  for (size_t a = 0; a < rays.size(); ++a) {
    for (size_t b = a + 1; b < rays.size(); ++b) {
      min_cosine = std::min(min_cosine, rays[a].dot(rays[b]));
    }
  }
  return std::acos(std::clamp(min_cosine, -1.0, 1.0)) * 180.0 / M_PI;
}

ShortBaselines FindShortBaselines(const Reconstruction& model,
                                  const ShortBaselineOptions& options) {
  options.Check();
  ShortBaselines result;
  const std::vector<Point3D>& points = model.Points3D();
  if (points.size() < 10) return result;
  std::vector<Eigen::Vector2d> plan;
  for (const Point3D& point : points) plan.push_back(point.xyz.head<2>());
  const PlanGrid grid(plan, options.cell_factor);
  result.cell_size = grid.CellSize();
  std::vector<std::vector<double>> angles(grid.NumCells());
  for (size_t j = 0; j < points.size(); ++j) {
    angles[grid.IndexOf(plan[j])].push_back(
        TriangulationAngleDeg(model, points[j]));
  }
  std::vector<double> median(angles.size(), 0.0);
  std::vector<char> flagged(angles.size(), 0);
  for (size_t index = 0; index < angles.size(); ++index) {
    std::vector<double>& cell = angles[index];
    if (static_cast<int>(cell.size()) < options.min_points_per_cell) continue;
    std::nth_element(cell.begin(), cell.begin() + cell.size() / 2, cell.end());
    median[index] = cell[cell.size() / 2];
    flagged[index] = median[index] < options.min_angle_deg;
  }
  // A stretch along a diagonal track crosses cells corner to corner.
  for (const std::vector<size_t>& component :
       grid.Components(flagged, true, options.min_cells)) {
    for (const size_t index : component) {
      result.cell_centres.push_back(grid.Centre(index));
      result.cell_median_angle_deg.push_back(median[index]);
    }
  }
  return result;
}

}  // namespace uw
