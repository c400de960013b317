// What uwcalib calibrate writes: the .cameramodel files, calibration.json
// and residual plots, all in one set (docs/uwcalib.md).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "calib/mrcal_calibration.h"

namespace uw {

// Writes into `dir`, all or nothing: camera-N.cameramodel per camera;
// calibration.json (lens model, RMS, outliers, warp, per camera its
// intrinsics, pose and per image the RMS of its inliers and its outliers);
// residuals.png (every corner's residual, outliers apart) and
// residuals_per_image.png (each image's inlier RMS). `globs` name the
// cameras; `command` goes into the files' comments.
void WriteCalibrationReport(const MrcalRigCalibration& result,
                            const std::vector<std::string>& globs,
                            const std::string& command,
                            const std::filesystem::path& dir);

}  // namespace uw
