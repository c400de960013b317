#include "laserscale/sparse_surface.h"

#include <cmath>

#include <gtest/gtest.h>

#include "common/mesh/ray_caster.h"
#include "common/util/error.h"
#include "common/util/random.h"

namespace uw {
namespace {

double Height(double x, double y) {
  return 0.2 * std::sin(x) + 0.1 * std::cos(0.7 * y);
}

// 4000 well-observed points on a gentle relief over 8 x 6 m, seen from
// cameras 2.5 m above (z up).
Reconstruction MakeModel(int num_points) {
  Reconstruction model;
  SplitMix64Stream rng(3);
  for (int k = 0; k < num_points; ++k) {
    Point3D point;
    point.point3D_id = k + 1;
    const double x = rng.Uniform(-4.0, 4.0);
    const double y = rng.Uniform(-3.0, 3.0);
    point.xyz = Eigen::Vector3d(x, y, Height(x, y));
    point.error = 0.3;
    point.track.resize(4);
    model.Points3D().push_back(point);
  }
  Camera camera;
  camera.camera_id = 1;
  camera.model_id = CameraModelId::kSimplePinhole;
  camera.width = 100;
  camera.height = 100;
  camera.params = {100, 50, 50};
  model.AddCamera(camera);
  Image image;
  image.image_id = 1;
  image.camera_id = 1;
  image.name = "a.png";
  // Looking down from (0, 0, 2.5): the camera's z is the world's -z.
  image.cam_from_world.rotation =
      Eigen::Quaterniond(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()));
  image.cam_from_world.translation =
      -(image.cam_from_world.rotation * Eigen::Vector3d(0, 0, 2.5));
  model.AddImage(image);
  return model;
}

TEST(SparseSurfaceMesh, FollowsTheReliefAndFacesTheCameras) {
  const TriangleMesh mesh = SparseSurfaceMesh(MakeModel(4000), {});
  const RayCaster caster(mesh);
  double max_error = 0.0;
  int hits = 0;
  for (double x = -3.0; x <= 3.0; x += 0.37) {
    for (double y = -2.0; y <= 2.0; y += 0.41) {
      const auto hit = caster.Intersect(Eigen::Vector3d(x, y, 2.5),
                                        -Eigen::Vector3d::UnitZ());
      ASSERT_TRUE(hit) << x << " " << y;
      ++hits;
      max_error =
          std::max(max_error, std::abs(hit->point_in_world.z() - Height(x, y)));
      // Counter-clockwise seen from the water: the normal points up.
      EXPECT_GT(hit->normal_in_world.z(), 0.5);
    }
  }
  // ~0.2 m grid over a relief of 0.2 m amplitude: a few mm of smoothing.
  EXPECT_LT(max_error, 0.01) << hits << " hits";
}

TEST(SparseSurfaceMesh, RefusesTooFewPoints) {
  EXPECT_THROW(SparseSurfaceMesh(MakeModel(5), {}), Error);
  SparseSurfaceOptions options;
  options.min_track_length = 5;  // every point has 4 observations
  EXPECT_THROW(SparseSurfaceMesh(MakeModel(4000), options), Error);
}

}  // namespace
}  // namespace uw
