// What the calibration tests share: a known camera, noisy views of a board,
// solve options, and Debian's mrcal-calibrate-cameras on the same corners.
// Test support only.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "calib/board.h"
#include "calib/corners_vnl.h"
#include "calib/mrcal_calibration.h"
#include "laserscale/laser_setup.h"

#include <opencv2/core.hpp>

namespace uw::testing_calibration {

// The truth: COLMAP's OPENCV camera, 1024 x 768, i.e. mrcal's
// LENSMODEL_OPENCV4 with the principal point 0.5 px lower (mrcal's pixel
// centres are at integers).
Camera TrueCamera();

// The board's corners seen by `camera` from each of `cam_from_board`, in
// mrcal's pixel convention, plus Gaussian noise of sigma_px drawn from
// `seed`; images "frame100.png", "frame101.png", ...
std::vector<BoardObservation> ViewsWithNoise(
    const Camera& camera, const CalibrationBoard& board,
    const std::vector<Rigid3d>& cam_from_board, double sigma_px, uint64_t seed);

MrcalCalibrationOptions Options(const std::string& lens_model, double focal_px,
                                int width, int height);

// The board of the laser tests: 9x7 inner corners, 8 cm squares.
CalibrationBoard LaserBoard();

// One image of a laser calibration session.
struct LaserBoardView {
  cv::Mat bgr;
  Rigid3d cam_from_board;
  std::vector<Eigen::Vector2d> spots;  // per laser, COLMAP's convention
};

// `num_distances` views of LaserBoard() from 0.6 to 3.6 m, tilted up to 10
// deg, rendered through `camera` (2x2 samples a pixel, noise σ 2 levels;
// white 150, so that a
// spot does not saturate), each laser's spot drawn where its beam meets
// the board: a Gaussian of σ 2 px and 100 levels in red (15 and 10 in
// green and blue).
std::vector<LaserBoardView> RenderLaserBoardViews(const Camera& camera,
                                                  const LaserSetup& setup,
                                                  int num_distances,
                                                  uint64_t seed);

// Writes the cameras' views as one `dir`/corners.vnl (a glob a camera) and
// runs mrcal-calibrate-cameras there (with /usr/bin/python3: the tool is
// Debian's python3-mrcal's) with options' lens model, seed focal length
// and image size and the board's geometry; it writes
// `dir`/camera-N.cameramodel. Returns what the tool printed; throws
// uw::Error with it if the tool fails.
std::string RunMrcalCalibrateCameras(const std::vector<RigCameraViews>& cameras,
                                     const CalibrationBoard& board,
                                     const MrcalCalibrationOptions& options,
                                     const std::vector<std::string>& globs,
                                     const std::filesystem::path& dir);

}  // namespace uw::testing_calibration
