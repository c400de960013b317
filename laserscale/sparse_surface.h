// A surface from a sparse model's points, for ray casting laser spots when
// no dense mesh exists yet: a heightfield over the points' best-fit plane
// (its normal turned towards the cameras), each grid node the
// Gaussian-weighted mean height of the well-observed points around it.
// It follows relief at the scale of the points' spacing only, so it suits
// seafloor surveys seen from above and is a stand-in for a real MVS mesh:
// a hit off by δ along the ray at range d biases FUM by about δ/d. Walls
// and overhangs need a real mesh.
#pragma once

#include "colmap_plugins/scene/model.h"
#include "common/mesh/mesh.h"

namespace uw {

struct SparseSurfaceOptions {
  // Grid spacing in model units; <= 0: twice the points' mean spacing.
  double grid_spacing = 0.0;
  // Points seen by fewer images, or with a larger mean reprojection error
  // (px), are left out.
  int min_track_length = 3;
  double max_reprojection_error_px = 2.0;
  // A node needs this many points within 1.5 grid spacings.
  int min_points_per_node = 3;

  void Check() const;
};

// Throws uw::Error when fewer than 10 points qualify or they are collinear.
TriangleMesh SparseSurfaceMesh(const Reconstruction& model,
                               const SparseSurfaceOptions& options);

}  // namespace uw
