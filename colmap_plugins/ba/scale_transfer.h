// Whether the images fix the distances between all the cameras. Two images
// that share only points no third image sees fix their relative pose up to
// scale: the length of their baseline is free, and only a point seen by 3
// images carries one baseline's length to the next.
//
// On the scarp's two-line plan with 120 tracked points per image (uwsim
// observe), the last three images of a line shared only two-view points
// with each other. Fused with 0.77 m navigation (positions and attitude),
// the noisy priors had 00132.png 9 cm along the line from 00131.png (78 cm
// true), and the adjustment put it 0.5 um from it, with CONVERGENCE and
// exit 0; the covariance then found their 45 points undetermined and
// refused. Without navigation the adjustment did not converge in 100
// iterations.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "colmap_plugins/scene/model.h"

namespace uw {

// The images outside the largest group that points seen by 3 or more images
// link (images i and j are linked when such a point is seen by both), in
// id order: their distance to the rest is not fixed by the images. Empty
// when every image is in one group. Necessary, not sufficient: two groups
// that share a single image still have a free relative scale, which this
// does not catch.
std::vector<image_t> ImagesWithoutScaleTransfer(const Reconstruction& model);

// The warning for such images (naming a few): with navigation priors their
// distances are the navigation's alone; without, the adjustment and its
// covariance are degenerate. None when there are none.
std::optional<std::string> ScaleTransferWarning(const Reconstruction& model,
                                                bool navigation_priors);

}  // namespace uw
