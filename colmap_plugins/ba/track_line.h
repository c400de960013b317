// Whether the navigation's positions alone fix the model's rotation: camera
// centres nearly on one line (a single survey pass) fix the rotation about
// that line only through their small scatter off it.
//
// On the breakwater's single pass (21 centres, 6 cm RMS across an 11 m
// line, priors 0.95 m horizontally and 2 cm in depth) the fused
// adjustment's linearised covariance put the roll about the pass at
// 5-8 deg; over 65 re-adjustments with known noise the pose NEES was 8.3
// against 6, with 4 trials above 20 (rotations 3 sigma off): the roll is
// set by the product of the model's lateral offsets, which the images fix
// only as well as their bending, and the depth priors, so its error is not
// the Gaussian the linearisation gives. With the log's roll and pitch as
// priors (--Nav.use_attitude 1) the rotation is fixed directly.
//
// A small survey has the same weakness without a line: the vent's 15
// centres (1.0 x 1.3 m RMS, 0.85 m horizontal navigation noise) fix the
// heading to about 9 deg, and over 100 fused re-adjustments the points'
// NEES was 3.71 +- 0.32 against 3 (poses 6.19), where the same plan
// without priors (held gauge 2.81, free network 3.04), with attitude
// priors (2.69) and with a 0.2 m navigation (3.19, heading to 2 deg) holds:
// a datum that weak (its scale too: 7 % RMS) is not Gaussian, and the
// world-frame sigmas come out too small.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "colmap_plugins/ba/bundle_covariance.h"
#include "colmap_plugins/ba/nav_bundle_adjuster.h"
#include "colmap_plugins/scene/model.h"

namespace uw {

// Above this median camera rotation sigma (deg) the priors' rotation is
// too weak for the linearisation: the vent's 8.9 failed, the seafloor
// survey's 4.3 held (NEES 3.06).
constexpr double kMaxPriorRotationSigmaDeg = 6.0;

// The median over the images that are not held of their largest rotation
// sigma (deg); 0 when every image is held.
double MedianRotationSigmaDeg(const BundleCovariance& covariance);

// The warning for a covariance in the priors' gauge without attitude
// priors whose median camera rotation sigma exceeds the bound; none
// otherwise.
std::optional<std::string> WeakRotationWarning(double median_rotation_sigma_deg,
                                               bool attitude_priors);

// The warning for position priors on such a track when no attitude prior
// holds the rotation; none otherwise (no priors, or attitude priors used).
// It advises --Nav.use_attitude 1 when some prior has a rotation, and says
// the log has none otherwise.
// The track is measured on the model's centres of the images with priors:
// the priors themselves scatter by their noise (0.95 m on the breakwater,
// more than the pass is wide).
std::optional<std::string> TrackLineWarning(
    const Reconstruction& model, const std::vector<ImagePosePrior>& priors,
    bool attitude_priors);

}  // namespace uw
