#include "colmap_plugins/align/mesh_frame.h"

#include <fmt/format.h>

#include "colmap_plugins/align/alignment_plausibility.h"
#include "common/util/error.h"
#include "common/util/median.h"

namespace uw {

MeshFrameCheck CheckMeshFrame(const std::vector<Rigid3d>& cams_from_world,
                              const RayCaster& mesh,
                              std::optional<double> typical_depth) {
  constexpr size_t kMaxCameras = 200;
  constexpr double kMinHitFraction = 0.25;
  constexpr double kDepthRatio = 3.0;
  MeshFrameCheck check;
  check.typical_depth = typical_depth;
  const size_t stride = std::max<size_t>(
      1, (cams_from_world.size() + kMaxCameras - 1) / kMaxCameras);
  std::vector<double> distances;
  for (size_t i = 0; i < cams_from_world.size(); i += stride) {
    const Rigid3d world_from_cam = cams_from_world[i].Inverse();
    const Eigen::Vector3d axis =
        world_from_cam.rotation * Eigen::Vector3d::UnitZ();
    ++check.num_cameras;
    if (const auto hit = mesh.Intersect(world_from_cam.translation, axis)) {
      distances.push_back(hit->distance);
    }
  }
  check.num_hits = distances.size();
  if (!distances.empty()) check.median_hit_distance = Median(distances);
  if (check.num_cameras == 0) {
    check.problem = "no camera to look at it";
  } else if (check.num_hits < kMinHitFraction * check.num_cameras) {
    check.problem = fmt::format(
        "only {} of {} cameras look at it (their optical axes meet it): it "
        "lies elsewhere, in another model's frame",
        check.num_hits, check.num_cameras);
  } else if (typical_depth && *typical_depth > 0.0 &&
             (*check.median_hit_distance > kDepthRatio * *typical_depth ||
              *check.median_hit_distance < *typical_depth / kDepthRatio)) {
    check.problem = fmt::format(
        "the cameras meet it {:.4g} units away (median) but see the model's "
        "points {:.4g} units away: another scale or frame",
        *check.median_hit_distance, *typical_depth);
  }
  return check;
}

MeshFrameCheck CheckMeshFrame(const Reconstruction& model,
                              const RayCaster& mesh) {
  std::vector<Rigid3d> cams_from_world;
  for (const Image& image : model.Images()) {
    cams_from_world.push_back(image.cam_from_world);
  }
  const std::vector<double> depths = ObservationDepths(model);
  return CheckMeshFrame(
      cams_from_world, mesh,
      depths.empty() ? std::nullopt : std::optional<double>(Median(depths)));
}

void RequireMeshInModelFrame(const MeshFrameCheck& check,
                             const std::string& mesh_path,
                             const std::string& model_path) {
  if (check.problem.empty()) return;
  throw ErrorAt(mesh_path, ": not in the frame of ", model_path, ": ",
                check.problem,
                ". Give the mesh made from this model (or transform it with "
                "the same similarity)");
}

}  // namespace uw
