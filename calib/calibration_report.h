// What uwcalib calibrate writes: the .cameramodel files, calibration.json
// and residual plots, all in one set (docs/uwcalib.md).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "calib/mrcal_calibration.h"
#include "calib/projection_uncertainty.h"

namespace uw {

// Writes into `dir`, all or nothing: camera-N.cameramodel per camera;
// calibration.json (lens model, RMS, outliers, warp, per camera its
// intrinsics, pose, per image the RMS of its inliers and its outliers, and
// its projection uncertainty on a 16-column grid); the figures
// residuals.png/.svg (every corner's residual, outliers apart) and
// residuals_per_image.png/.svg (each image's inlier RMS, by name); and
// projection_uncertainty.png (a rig's:
// projection_uncertainty-camera-N.png), the heat map of `uncertainty`'s
// map. `globs` name the cameras; `command` goes into the files' comments.
void WriteCalibrationReport(const MrcalRigCalibration& result,
                            const std::vector<std::string>& globs,
                            const std::string& command,
                            const ProjectionUncertaintyOptions& uncertainty,
                            const std::filesystem::path& dir);

// What uwcalib calibrate prints of `result`, a line each: per camera its
// views and outliers (after camera 0 also its baseline, the board's units),
// then per camera the projection uncertainty at the image's centre for a
// point uncertainty.distance out (ProjectionUncertaintyAtPixel).
std::vector<std::string> DescribeRigCalibration(
    const MrcalRigCalibration& result,
    const ProjectionUncertaintyOptions& uncertainty);

}  // namespace uw
