#include "colmap_plugins/align/mesh_frame.h"

#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include "colmap_plugins/scene/model_testing.h"

#include "common/mesh/test_meshes.h"
#include "common/util/error_testing.h"

namespace uw {
namespace {

// A 20 m x 20 m floor at z = 0 and a model of 5 x 5 down-looking cameras
// 3 m above it, each seeing a point of the floor below it.
struct Scene {
  TriangleMesh floor;
  Reconstruction model;
};

Scene FloorScene() {
  Scene scene;
  AddGrid({-10, -10, 0}, {20, 0, 0}, {0, 20, 0}, 10, 10, &scene.floor);
  scene.model.AddCamera(TestPinholeCamera(1, 100, 100.0));
  // Looking down: camera z along world -z.
  const Eigen::Quaterniond cam_from_world(
      Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()));
  image_t id = 0;
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 5; ++j) {
      const Eigen::Vector3d centre(2.0 * i - 4.0, 2.0 * j - 4.0, 3.0);
      Image image;
      image.image_id = ++id;
      image.camera_id = 1;
      image.name = std::to_string(id) + ".png";
      image.cam_from_world.rotation = cam_from_world;
      image.cam_from_world.translation = -(cam_from_world * centre);
      scene.model.AddImage(image);
      Point3D point;
      point.point3D_id = id;
      point.xyz = Eigen::Vector3d(centre.x(), centre.y(), 0.0);
      point.track.push_back({id, 0});
      scene.model.AddPoint3D(point);
    }
  }
  return scene;
}

TEST(MeshFrame, TheModelsOwnMeshPasses) {
  const Scene scene = FloorScene();
  const MeshFrameCheck check =
      CheckMeshFrame(scene.model, RayCaster(scene.floor));
  EXPECT_EQ(check.problem, "");
  EXPECT_EQ(check.num_cameras, 25u);
  EXPECT_EQ(check.num_hits, 25u);
  EXPECT_NEAR(*check.median_hit_distance, 3.0, 1e-9);
  EXPECT_NEAR(*check.typical_depth, 3.0, 1e-9);
  // A mesh trimmed to half the survey still lies in the frame.
  TriangleMesh half;
  AddGrid({-10, -10, 0}, {10, 0, 0}, {0, 20, 0}, 5, 10, &half);
  EXPECT_EQ(CheckMeshFrame(scene.model, RayCaster(half)).problem, "");
}

// Another model's mesh 25 m away, and one in other units (x 10): refused,
// naming both files.
TEST(MeshFrame, AMeshOfAnotherFrameIsRefused) {
  const Scene scene = FloorScene();
  TriangleMesh shifted;
  AddGrid({15, -10, 0}, {20, 0, 0}, {0, 20, 0}, 10, 10, &shifted);
  const MeshFrameCheck away = CheckMeshFrame(scene.model, RayCaster(shifted));
  EXPECT_EQ(away.num_hits, 0u);
  ExpectErrorContaining(
      [&] { RequireMeshInModelFrame(away, "dense.ply", "sparse/0"); },
      "dense.ply: not in the frame of sparse/0: only 0 of 25 cameras look "
      "at it");
  TriangleMesh scaled = scene.floor;
  for (Eigen::Vector3d& vertex : scaled.vertices) vertex.z() = -27.0;
  const MeshFrameCheck far = CheckMeshFrame(scene.model, RayCaster(scaled));
  EXPECT_EQ(far.num_hits, 25u);
  EXPECT_NE(far.problem.find("meet it 30 units away (median) but see the "
                             "model's points 3 units away"),
            std::string::npos)
      << far.problem;
  // Without points to compare with, only whether the cameras look at it.
  std::vector<Rigid3d> cams;
  for (const Image& image : scene.model.Images()) {
    cams.push_back(image.cam_from_world);
  }
  EXPECT_EQ(CheckMeshFrame(cams, RayCaster(scaled), std::nullopt).problem, "");
}

}  // namespace
}  // namespace uw
