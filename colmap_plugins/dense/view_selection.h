// What the sparse model tells dense matching about each image: which other
// images to match it with, and between which depths its surface lies.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "colmap_plugins/scene/model.h"

namespace uw {

struct ViewSelectionOptions {
  // Source images per reference image.
  int num_neighbors = 4;
  // A pair needs this many shared 3D points...
  int min_shared_points = 30;
  // ...seen under a median triangulation angle in this range (degrees).
  // Below it depth is poorly constrained; above it the images look too
  // different for window matching.
  double min_triangulation_angle_deg = 3.0;
  double max_triangulation_angle_deg = 45.0;
  // Depth range: these quantiles of the depths of the image's 3D points,
  // widened by `depth_margin` (fraction) on either side.
  double depth_quantile = 0.02;
  double depth_margin = 0.15;

  void Check() const;  // throws uw::Error naming the bad field
};

struct ViewNeighbors {
  // Indices into Reconstruction::Images(), best first.
  std::vector<size_t> neighbors;
  // Depth range (model units along the optical axis); unset when the image
  // sees fewer than 10 points.
  std::optional<std::pair<double, double>> depth_range;
};

// One entry per image of model.Images(), in that order. Pairs are ranked by
// shared points x min(1, angle / 10 deg), favouring overlapping pairs with a
// useful baseline, as COLMAP's view selection does.
std::vector<ViewNeighbors> SelectViews(const Reconstruction& model,
                                       const ViewSelectionOptions& options);

}  // namespace uw
