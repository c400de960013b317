// A calibrated camera (mrcal's .cameramodel) for COLMAP and OpenCV.
#pragma once

#include <string>

#include "calib/mrcal_calibration.h"
#include "colmap_plugins/scene/model.h"

namespace uw {

// The COLMAP camera that projects exactly as the mrcal model does:
//   LENSMODEL_PINHOLE  -> PINHOLE
//   LENSMODEL_OPENCV4  -> OPENCV       (fx fy cx cy k1 k2 p1 p2)
//   LENSMODEL_OPENCV5  -> FULL_OPENCV  (k4 = k5 = k6 = 0)
//   LENSMODEL_OPENCV8  -> FULL_OPENCV
//   LENSMODEL_OPENCV12 -> FULL_OPENCV  only if its thin-prism terms are 0
// cx and cy gain 0.5 (COLMAP's pixel centres are at +0.5, mrcal's at
// integers); nothing else changes. Other models have no COLMAP equivalent:
// uw::Error says so and what to calibrate instead. `where` names the source.
Camera ColmapCameraFromMrcal(const MrcalCameraModel& model,
                             const std::string& where);

// OpenCV's calibration YAML (cv::FileStorage, the keys of OpenCV's
// calibration sample): image_width, image_height, camera_matrix,
// distortion_coefficients (OpenCV's order, as many as the model has).
// Pixel convention unchanged (OpenCV's is mrcal's). Refuses models OpenCV
// cannot represent.
std::string OpenCvYamlFromMrcal(const MrcalCameraModel& model,
                                const std::string& where);

}  // namespace uw
