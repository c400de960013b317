// The views of each camera of a synchronised rig, from one corners.vnl:
// a glob of image names per camera, as mrcal-calibrate-cameras takes them.
#pragma once

#include <string>
#include <vector>

#include "calib/corners_vnl.h"
#include "calib/mrcal_calibration.h"

namespace uw {

// The frame of an image of a rig: the last run of digits in its name's
// stem (left01.jpg and right01.jpg are frame 1), as
// mrcal-calibrate-cameras pairs them. Throws uw::Error naming the image
// when it has no digit.
int FrameOfImage(const std::string& image);

// The views of each camera: the observations whose image matches its glob
// (fnmatch; the first glob that matches wins, images matching none are no
// camera's), each with its frame. One glob: every observation, its frame
// its index in `observations`. Throws uw::Error naming `where` when a glob
// matches no image.
std::vector<RigCameraViews> SplitViewsByCamera(
    const std::vector<BoardObservation>& observations,
    const std::vector<std::string>& globs, const std::string& where);

}  // namespace uw
