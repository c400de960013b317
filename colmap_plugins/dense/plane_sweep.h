// Depth of every pixel of a reference image by plane sweeping (Collins 1996;
// Gallup et al. 2007) on the CPU: for fronto-parallel planes at depths
// evenly spaced in inverse depth, each source image is warped into the
// reference through the plane's homography and compared with it by
// normalised cross-correlation (NCC) over a small window. A pixel takes the
// depth of its best plane, refined by a parabola through the neighbouring
// planes' costs.
//
// Robustness: the cost of a plane is the mean of the `num_best_sources`
// lowest costs over the sources, so a source that is occluded does not veto
// it (COLMAP's patch-match stereo does the same with its view sampling); a
// source that does not see the pixel at that depth counts as uncorrelated,
// so that a pixel seen by a single source still gets a depth. Pixels whose best
// cost is high, whose window is textureless or whose best plane is the first or
// last are left without a depth: holes are filled later by the surface, never
// by guesses here.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "colmap_plugins/dense/pinhole_view.h"

namespace uw {

struct PlaneSweepOptions {
  // NCC window: (2 r + 1)^2 pixels.
  int window_radius = 3;
  // Planes are spaced so that the image of a point moves by at most this
  // many pixels from one plane to the next in the source with the longest
  // baseline.
  double plane_step_px = 1.0;
  // Costs averaged per plane (see above).
  int num_best_sources = 2;
  // 1 - NCC (mean over the sources that see the pixel among the best)
  // above which a pixel gets no depth.
  double max_cost = 0.4;
  // Standard deviation of the reference window's grey levels (on [0, 1])
  // below which a pixel gets no depth: NCC of noise is meaningless.
  double min_texture = 0.004;

  void Check() const;  // throws uw::Error naming the bad field
};

struct DepthMap {
  // CV_32F depth along the reference's optical axis; 0 = none.
  cv::Mat depth;
  // CV_32F aggregated 1 - NCC of the chosen plane (where depth > 0).
  cv::Mat cost;
  int num_planes = 0;
};

// Throws uw::Error for no source or more than 16, or a depth range that is
// not 0 < min_depth < max_depth.
DepthMap PlaneSweepDepth(const PinholeView& reference,
                         const std::vector<const PinholeView*>& sources,
                         double min_depth, double max_depth,
                         const PlaneSweepOptions& options);

}  // namespace uw
