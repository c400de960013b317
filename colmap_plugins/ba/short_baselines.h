// Where a model's depth rests on short baselines: every image that sees the
// points there was taken from nearly the same place (a vehicle that hovered
// while the images around were dropped, a stretch whose neighbours the
// mapper did not register). The covariance shows it as weak points, but
// so do a survey's edges; this names the cause (docs/covariance.md, "Map").
//
// A point's triangulation angle is the widest angle between two of its
// viewing rays (from the centres of the images that see it). The points
// are binned in plan view in cells of `cell_factor` times their mean
// spacing, as coverage gaps are (coverage_gaps.h); a cell is short-baseline
// when it holds at least `min_points_per_cell` points and the median of
// their angles is below `min_angle_deg`; a stretch is at least `min_cells`
// such cells connected side by side (edge-adjacent or diagonal).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "colmap_plugins/scene/model.h"

namespace uw {

struct ShortBaselineOptions {
  // Below 5 deg the depth's sigma exceeds ~11x the lateral one (1 /
  // tan(angle)); COLMAP's mapper keeps points down to 1.5 deg.
  double min_angle_deg = 5.0;
  double cell_factor = 4.0;
  int min_points_per_cell = 3;
  int min_cells = 2;

  void Check() const;  // throws uw::Error naming the field
};

struct ShortBaselines {
  double cell_size = 0.0;                     // m
  std::vector<Eigen::Vector2d> cell_centres;  // of the flagged cells
  std::vector<double> cell_median_angle_deg;  // per flagged cell
  double Area() const {
    return cell_size * cell_size * static_cast<double>(cell_centres.size());
  }
};

// The widest angle (deg) between the rays from the centres of the images in
// `point`'s track; 0 for a track of fewer than two images.
double TriangulationAngleDeg(const Reconstruction& model, const Point3D& point);

// Fewer than 10 points: no cells.
ShortBaselines FindShortBaselines(const Reconstruction& model,
                                  const ShortBaselineOptions& options);

}  // namespace uw
