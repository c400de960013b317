// Where a model has no points although the survey surrounds the place: a
// coverage gap (docs/covariance.md, "Map"). The covariance cannot show one,
// since it has no points there to give a sigma to; the uncertainty map and
// covariance.json mark it instead.
//
// The points in plan view are binned in square cells of `cell_factor` times
// their mean spacing (sqrt(bounding area / count)), where an empty cell by
// chance is rare (~e^-16 for factor 4). An empty cell is a gap cell when
// occupied cells lie on all four sides of it (left, right, below, above)
// within `max_gap_cells`: the survey surrounds it. A gap is at least
// `min_cells` such cells connected side by side: a lone empty cell is a
// notch in a ragged edge (seen on the uwsim survey), not a hole. The edges
// of the survey and the inner corner of an L-shaped one are not gaps.
#pragma once

#include <vector>

#include <Eigen/Core>

namespace uw {

struct CoverageGapOptions {
  double cell_factor = 4.0;
  int max_gap_cells = 20;
  int min_cells = 3;

  void Check() const;  // throws uw::Error naming the field
};

struct CoverageGaps {
  double cell_size = 0.0;                     // m
  std::vector<Eigen::Vector2d> cell_centres;  // of the gap cells, plan view
  double Area() const {
    return cell_size * cell_size * static_cast<double>(cell_centres.size());
  }
};

// Fewer than 10 points: no cells, no gaps.
CoverageGaps FindCoverageGaps(const std::vector<Eigen::Vector2d>& points,
                              const CoverageGapOptions& options);

}  // namespace uw
