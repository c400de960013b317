// A calibration board's pose in a calibrated camera, from its corners.
#pragma once

#include <optional>

#include "calib/board.h"
#include "calib/corners_vnl.h"
#include "colmap_plugins/scene/model.h"

namespace uw {

// PnP on the found corners' rays through `camera` (its distortion removed
// exactly), refined by Levenberg-Marquardt. The corners are in mrcal's
// pixel convention, as the detectors and corners.vnl give them; `camera`
// is COLMAP's (pixel centres at +0.5). Empty with fewer than 4 corners or
// when PnP fails.
std::optional<Rigid3d> EstimateBoardPose(const Camera& camera,
                                         const CalibrationBoard& board,
                                         const BoardObservation& observation);

}  // namespace uw
