// Removes what a closed surface (Poisson) invents away from the data: the
// triangles no fused point supports, the long thin ones that bridge gaps,
// and the small islands left after that.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "common/mesh/mesh.h"

namespace uw {

struct TrimmingOptions {
  // A triangle is supported when a point lies within this distance of its
  // centroid (model units); must be set (> 0).
  double max_distance = 0.0;
  // Triangles with an edge longer than this times the median edge go.
  double max_edge_factor = 4.0;
  // Connected components with fewer triangles than this fraction of the
  // largest one go.
  double min_component_fraction = 0.01;

  void Check() const;  // throws uw::Error naming the bad field
};

// The kept triangles, in order, and the vertices they use, renumbered in
// order of first use. Throws uw::Error for a vertex index out of range.
TriangleMesh TrimUnsupported(const TriangleMesh& mesh,
                             const std::vector<Eigen::Vector3d>& points,
                             const TrimmingOptions& options);

}  // namespace uw
