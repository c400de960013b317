// uwcalib lasers' method (thesis ch. 3 §2.4, docs/uwcalib.md): laser lines
// from images of a calibration board held at many distances, the lasers
// on. In each image the board's pose from its corners (a calibrated
// camera) and the spots of the lasers' colour; each spot's ray cut with
// the board's plane; the points sorted into num_lasers lines by sequential
// RANSAC and a line fitted to each (calib/laser_line_fit.h).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "calib/board.h"
#include "calib/colour_spots.h"
#include "calib/laser_line_fit.h"
#include "colmap_plugins/scene/model.h"
#include "laserscale/laser_setup.h"

namespace uw {

struct BoardLaserCalibrationOptions {
  int num_lasers = 0;                // lasers on in the images (required)
  std::string setup_name = "board";  // the set-up's name in lasers.json
  // The spots: their colour is the lasers' colour in lasers.json.
  ColourSpotOptions spots;
  LaserLineFitOptions fit;

  // Throws uw::Error naming the first bad field.
  void Check() const;
};

struct BoardLaserCalibration {
  // Named as options.setup_name, the lasers L0, L1, ... in the colour of
  // the spots.
  LaserSetup setup;
  std::vector<LaserLineFit> fits;  // per laser of `setup`
  int num_images_with_board = 0;
};

// What each image gave, as it is done: the board's pose found or not (an
// image without it is skipped), and its spots.
using BoardLaserImageCallback = std::function<void(
    const std::string& image, bool board_found, size_t num_spots)>;

// The images `names` of `images_dir` (8-bit colour, camera's size) seen by
// `camera` (COLMAP's; distortion removed exactly). Throws uw::Error naming
// the image for one that cannot be read or is not the camera's size,
// naming images_dir when fewer than options.fit.min_distances images show
// the board, and as FitLaserLines when a laser cannot be fitted.
BoardLaserCalibration CalibrateLasersFromBoardImages(
    const Camera& camera, const CalibrationBoard& board,
    const std::string& images_dir, const std::vector<std::string>& names,
    const BoardLaserCalibrationOptions& options,
    const BoardLaserImageCallback& on_image = nullptr);

// One line of uwcalib lasers' output for a fitted laser: its spots' depth
// range, origin and direction with their sigma, the line's RMS.
std::string DescribeLaserLineFit(const LaserLineFit& fit);

}  // namespace uw
