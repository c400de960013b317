// Synthetic calibration images: a chessboard seen through any COLMAP
// camera, with its true corners (uwcalib's ground truth).
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "calib/board.h"
#include "colmap_plugins/scene/model.h"

namespace uw::sim {

struct BoardImageOptions {
  int supersampling = 4;      // samples per pixel side (edges anti-aliased)
  double black_level = 30.0;  // 8-bit levels
  double white_level = 220.0;
  double background_level = 110.0;  // beyond the board's white margin
  double noise_sigma = 0.0;         // Gaussian, levels
  // The white margin around the outer squares, in squares.
  double margin_squares = 1.0;
};

struct BoardImage {
  cv::Mat image;  // 8-bit grey, camera.width x camera.height
  // True corners in mrcal's order and convention ((0, 0) = centre of the
  // top-left pixel, i.e. COLMAP's pixel minus 0.5).
  std::vector<Eigen::Vector2d> corners;
  bool all_corners_inside = false;  // every corner at least 2 px inside
};

// Renders the board (corners at CornersInBoard(), black square between the
// first four corners' neighbours as OpenCV draws it) by casting each
// sub-sample's ray through the camera model onto the board plane z = 0.
// Noise is drawn from `seed` alone, row by row: the same seed gives the
// same image.
BoardImage RenderBoardImage(const Camera& camera, const Rigid3d& cam_from_board,
                            const CalibrationBoard& board,
                            const BoardImageOptions& options, uint64_t seed);

// `count` poses of the board in front of the camera at distances
// [min_distance_m, max_distance_m], tilted up to max_tilt_deg, drawn from
// `seed`, each keeping the whole board inside the image with a margin.
std::vector<Rigid3d> RandomBoardPoses(const Camera& camera,
                                      const CalibrationBoard& board, int count,
                                      double min_distance_m,
                                      double max_distance_m,
                                      double max_tilt_deg, uint64_t seed);

}  // namespace uw::sim
