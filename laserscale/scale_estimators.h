// The scale of a model from where laser beams hit it (thesis ch. 3 §2.3,
// ch4 spec §3): each estimator compares a length known in metres, m, with
// the same length measured through the model, m̂, and returns
//   s = m / m̂      (multiply the model by s to get metres),
// so a model k times too large gives s = 1/k; the scale error of a model
// meant to be metric is ε_s = s − 1 (negative: the model is too large).
//
// Inputs are the beams' hits on the model (ray casts of the detected spots,
// model units) in the camera frame of the image (COLMAP's: x right, y down,
// z forward) or in the world frame with the camera centre, as each method
// needs. An estimate that cannot be made (a hit behind the camera, a beam
// parallel to the camera plane, coincident hits, a non-finite input) comes
// back without a scale and with the reason, never as NaN.
#pragma once

#include <optional>
#include <string>

#include <Eigen/Core>

#include "laserscale/laser_setup.h"

namespace uw {

struct ScaleEstimate {
  std::optional<double> scale;  // s = m / m̂
  std::string problem;          // why there is no scale; empty with one
};

// Fully unconstrained method (FUM, thesis Eq. 4): the hit is traced back
// along the laser's calibrated direction v to the camera plane Π (z = 0),
//   Ô = X − (X_z / v_z) v,
// and the origin's known distance from the optical centre, m = |O|, is
// compared with |Ô|. Any laser geometry; one laser suffices; exact on any
// terrain when the calibration is.
ScaleEstimate FumScale(const Laser& laser, const Eigen::Vector3d& hit_in_cam);

// Partially constrained method (PCM, thesis ch. 3 Eq. 4-5): two parallel
// beams whose origins are equidistant from the camera centre, a known
// perpendicular separation d apart. The beams' direction is taken as the
// ray from the camera centre C to the midpoint of the hits, so
//   d̂ = sin(α) |X2 − X1|,  α = ∠(X2 − X1, (X1 + X2)/2 − C).
// Exact when the origins are symmetric about C; otherwise off by about the
// hits' depth difference times the beams' misalignment with that ray.
ScaleEstimate PcmScale(const Eigen::Vector3d& hit1_in_world,
                       const Eigen::Vector3d& hit2_in_world,
                       const Eigen::Vector3d& camera_center_in_world,
                       double separation_m);

// The simplistic baseline: the distance between two hits taken as the known
// distance between the beams (right only for parallel beams on a surface
// perpendicular to them).
ScaleEstimate DirectScale(const Eigen::Vector3d& hit1_in_world,
                          const Eigen::Vector3d& hit2_in_world,
                          double separation_m);

}  // namespace uw
