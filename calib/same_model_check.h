// Points from two models must never meet in one laser calibration (thesis
// [L3722-L3723]): each model has its own scale, and a line through points
// of two scales points the wrong way. The laser images' poses
// (poses.json) and the surface (mesh) must therefore both belong to the
// model named on the command line; these checks refuse them otherwise.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/mesh/ray_caster.h"
#include "laserscale/laser_poses_io.h"

namespace uw {

// Each localized image's inlier correspondences name 3D points of the
// model it was localized against: at least half of them must be points of
// `model_points` (to 1e-9 relative; a model whose points were filtered
// since still passes). Throws uw::Error naming poses_where, the image and
// model_where otherwise.
void CheckPosesUseModelPoints(const std::vector<Eigen::Vector3d>& model_points,
                              const std::vector<LocalizedImage>& images,
                              const std::string& poses_where,
                              const std::string& model_where);

// Rays from the localized cameras through (up to 20 per image of) their
// inlier pixels must meet the mesh at the depth of the inlier points: the
// median of hit distance / point distance within max_ratio_error of 1, and
// at least half the rays hitting. Throws uw::Error naming mesh_where, with
// the ratio (a mesh of another model is off by the ratio of the scales).
void CheckMeshFitsPoses(const RayCaster& caster,
                        const std::vector<LocalizedImage>& images,
                        const std::string& mesh_where,
                        double max_ratio_error = 0.05);

}  // namespace uw
