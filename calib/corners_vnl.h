// mrcal's corners.vnl: the board corners found in each calibration image,
// the file `mrgingham` writes and `mrcal-calibrate-cameras --corners-cache`
// reads (docs/formats.md#cornersvnl).
//
//   # filename x y level
//   left01.jpg 244.211 94.061 0       <- grid_width * grid_height rows per
//   ...                                  image, mrcal's corner order
//   left02.jpg - - -                  <- one row: no board in this image
//
// Pixels follow mrcal and OpenCV: (0, 0) is the centre of the top-left
// pixel (COLMAP's convention is shifted by +0.5). The fourth column is
// either mrgingham's pyramid level (weight 2^-level, the default mrcal
// reads) or a weight (mrcal-calibrate-cameras --corners-cache-has-weights);
// "-" or a negative value marks a corner that was not found.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

namespace uw {

// The corners of one board in one image.
struct BoardObservation {
  std::string image;  // as named in the file: no white space
  // Empty when no board was found; else one per board corner, mrcal's order.
  std::vector<Eigen::Vector2d> pixels;
  std::vector<double> weights;  // > 0: found; <= 0: not found

  bool Found() const { return !pixels.empty(); }
  int NumFoundCorners() const;
};

enum class CornerWeightColumn {
  kLevel,   // "# filename x y level", as mrgingham writes
  kWeight,  // "# filename x y weight"
};

// The text of a corners.vnl. `comment` lines (e.g. the command line) go
// first as "## ..." lines. With kLevel every found corner's weight must be
// a power of 1/2. Throws uw::Error naming the image for non-finite values,
// a wrong number of corners, an image name with white space or a weight
// the column cannot hold.
std::string FormatCornersVnl(const std::vector<BoardObservation>& observations,
                             CornerWeightColumn column,
                             const std::vector<std::string>& comments);

struct CornersVnl {
  CornerWeightColumn column = CornerWeightColumn::kLevel;
  std::vector<BoardObservation> observations;  // in file order
};

// Parses corners.vnl text as mrcal reads it; the legend line
// "# filename x y level|weight" (if any) says what the fourth column holds,
// level otherwise. `num_corners` is the board's (0: take the first image's
// count). Every image must have num_corners rows or one "- - -" row, in one
// block. Throws uw::Error naming `where`, the line and the image.
CornersVnl ParseCornersVnl(const std::string& text, const std::string& where,
                           int num_corners);

CornersVnl ReadCornersVnl(const std::string& path, int num_corners);

}  // namespace uw
