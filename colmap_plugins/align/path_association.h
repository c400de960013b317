// Aligning a reconstructed camera path to a navigation path when the
// cameras are not synchronised with the navigation (ch4 spec §7.3): each
// camera centre is associated with the closest point of the navigation
// polyline, the similarity is re-estimated from those pairs, and the two
// steps repeat (ICP on trajectories) until the associations stop moving.
//
// Closest points carry no information along a straight stretch of path: the
// initial association (by time when the image times are roughly known, by
// arc length in image order otherwise) fixes where the cameras sit along
// it, and only the path's curvature corrects that. Use it where the path
// shape is unambiguous (turns, depth changes), as the thesis says.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "colmap_plugins/align/similarity.h"

namespace uw {

// A navigation path in the target frame, sampled in time order. Samples of
// different dives are never joined.
struct TimedPath {
  std::vector<double> times_s;
  std::vector<Eigen::Vector3d> positions;
  // One per sample or empty; interpolated along segments.
  std::vector<Eigen::Matrix3d> covariances;
  // One per sample or empty (one dive).
  std::vector<int> dives;

  // Throws uw::Error on sizes that differ, non-finite values, or times that
  // do not increase within a dive.
  void Check() const;
};

struct PathAssociationOptions {
  SimilarityOptions similarity;
  // Closest points slide along the path slowly (linear convergence): a few
  // hundred iterations of O(cameras x samples) each.
  int max_iterations = 500;
  // Converged when no associated point moves by more than this fraction of
  // the path's extent between two iterations (0.1 mm per km).
  double tolerance = 1e-7;

  void Check() const;
};

struct PathAssociationResult {
  // The similarity of the last association, with its inliers and residuals
  // (camera centre to its closest path point).
  SimilarityResult similarity;
  // Per camera: the associated point of the path (target frame) and the
  // time there (linear along the segment).
  std::vector<Eigen::Vector3d> associated_positions;
  std::vector<double> associated_times_s;
  int iterations = 0;
  bool converged = false;
};

// centres_in_a: the reconstructed camera centres in acquisition order.
// centre_times_s (optional, one per centre): their approximate times on the
// path's clock, for the initial association; without them, centres and
// path are matched by arc-length fraction. Throws uw::Error for a path of
// fewer than 2 samples, and whatever EstimateSimilarity throws.
PathAssociationResult AlignToPathByClosestPoints(
    const std::vector<Eigen::Vector3d>& centres_in_a,
    const std::vector<double>* centre_times_s, const TimedPath& path_in_b,
    const PathAssociationOptions& options);

}  // namespace uw
