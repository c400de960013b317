// Whether a mesh lies in a model's frame: a mesh of another model, of the
// same model before an alignment, or in other units is drawn and measured
// as if it were this one (a report once drew one 25 m from the cameras).
// The cameras must look at it, from about as far as they see the model's
// own points.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "colmap_plugins/scene/model.h"
#include "common/mesh/ray_caster.h"

namespace uw {

struct MeshFrameCheck {
  size_t num_cameras = 0;  // optical axes cast (at most 200, spread evenly)
  size_t num_hits = 0;     // that meet the mesh in front of the camera
  std::optional<double> median_hit_distance;  // along the axis
  std::optional<double> typical_depth;  // median depth of the model's points
  // Empty when the mesh is plausibly in the frame; else why not.
  std::string problem;
};

// Casts the optical axis of (up to 200 of) `cams_from_world` onto the mesh.
// Implausible when fewer than a quarter meet it, or (with `typical_depth`,
// ObservationDepths' median) when the median distance to the hits lies
// outside a third to three times that depth: another frame or other units.
MeshFrameCheck CheckMeshFrame(const std::vector<Rigid3d>& cams_from_world,
                              const RayCaster& mesh,
                              std::optional<double> typical_depth);
// The same for a model's cameras and points.
MeshFrameCheck CheckMeshFrame(const Reconstruction& model,
                              const RayCaster& mesh);

// Throws uw::Error naming the mesh and the model when CheckMeshFrame finds
// a problem.
void RequireMeshInModelFrame(const MeshFrameCheck& check,
                             const std::string& mesh_path,
                             const std::string& model_path);

}  // namespace uw
