// CheckMeshFrame (colmap_plugins/align/mesh_frame.h) on uwsim's surveys of
// every world: each world's own mesh is in its cameras' frame, and the
// same mesh moved by 25 m is not. uwsim's true model has no points; a
// reconstruction's lie on the surface, so their depth is stood in for by
// the own mesh's hit distance. Without it the moved scarp passes: its wall
// runs on past 25 m and the cameras still meet it, only 25 m farther.
#include <iostream>

#include <gtest/gtest.h>

#include "colmap_plugins/align/mesh_frame.h"
#include "colmap_plugins/scene/model_io.h"
#include "common/mesh/mesh.h"
#include "sim/generate.h"
#include "tests/support/process.h"
#include "tests/support/world_plans.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

TEST(MeshFrameWorlds, EveryWorldsMeshIsInItsFramesAndNotMoved) {
  const fs::path dir = testing::FreshTestDir("uw_mesh_frame_worlds");
  for (const sim::WorldKind world : testing::AllWorlds()) {
    for (const uint64_t seed : {1u, 2u}) {
      const fs::path out = testing::WorldPlan(dir, world, seed);
      const Reconstruction model = ReadModel(out / "truth");
      const TriangleMesh mesh = ReadPly(out / "truth" / "mesh.ply");
      const MeshFrameCheck own = CheckMeshFrame(model, RayCaster(mesh));
      TriangleMesh moved = mesh;
      for (Eigen::Vector3d& vertex : moved.vertices) {
        vertex += Eigen::Vector3d(25.0, 25.0, 0.0);
      }
      std::vector<Rigid3d> cams;
      for (const Image& image : model.Images()) {
        cams.push_back(image.cam_from_world);
      }
      const MeshFrameCheck away =
          CheckMeshFrame(cams, RayCaster(moved), own.median_hit_distance);
      std::cout << "[ figures ] " << sim::WorldKindName(world) << " seed "
                << seed << ": own mesh " << own.num_hits << " of "
                << own.num_cameras << " cameras, median "
                << own.median_hit_distance.value_or(-1.0)
                << "; moved 25 m: " << away.num_hits << " of "
                << away.num_cameras << "\n";
      EXPECT_EQ(own.problem, "") << out;
      EXPECT_NE(away.problem, "") << out;
    }
  }
}

}  // namespace
}  // namespace uw
