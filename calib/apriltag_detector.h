// AprilTags in an image, with libapriltag 3 (Debian's): plain tags of any
// family it ships, and Kalibr's AprilGrid tags, whose black border is two
// cells wide (stock tag36h11 expects one and decodes none of them).
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace uw {

struct AprilTagOptions {
  // tag36h11, tag25h9, tag16h5, tagStandard41h12, tagCircle21h7, ...
  std::string family = "tag36h11";
  // Width of the black border in cells: 1 for AprilTag's own layout, 2 for
  // Kalibr's AprilGrid (the same codes, bits one cell further in).
  int border_cells = 1;
  // libapriltag's decimation and edge refinement. With 1 and false its
  // corners are in one pixel convention (in 3.3 other settings mix them),
  // and match the AprilTag project's reference detections.
  double quad_decimate = 1.0;
  bool refine_edges = false;
  int max_hamming = 2;  // bits corrected (libapriltag: at most 2)
  int num_threads = 1;

  void Check() const;
};

struct AprilTagDetection {
  int id = -1;
  int hamming = 0;
  double decision_margin = 0.0;
  // The outer corners of the black border, as libapriltag orders them: the
  // tag's own (-1, 1), (1, 1), (1, -1), (-1, -1), i.e. lower left, lower
  // right, upper right, upper left of the upright tag. Pixels in mrcal's
  // and OpenCV's convention ((0, 0) = centre of the top-left pixel).
  std::array<Eigen::Vector2d, 4> corners;
};

// The tags of `options.family` in an 8-bit grey or BGR image, ordered by id
// (then by their first corner). Throws uw::Error for an unknown family or a
// bad image.
std::vector<AprilTagDetection> DetectAprilTags(const cv::Mat& image,
                                               const AprilTagOptions& options);

}  // namespace uw
