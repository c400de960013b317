#include "colmap_plugins/align/mesh_comparison.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include <tbb/task_arena.h>

#include "common/mesh/test_meshes.h"
#include "common/util/error.h"
#include "common/util/error_testing.h"

namespace uw {
namespace {

constexpr double kHeight = 8.0;

// The true seafloor: z = 0 over [0, 10]^2 in 40 x 40 quads of 0.25 m,
// facing up.
TriangleMesh Seafloor() {
  TriangleMesh mesh;
  AddGrid(Eigen::Vector3d::Zero(), Eigen::Vector3d(10, 0, 0),
          Eigen::Vector3d(0, 10, 0), 40, 40, &mesh);
  return mesh;
}

// Looking straight down from `centre`: image x along world x, image y along
// world -y (180 degrees about x).
Image DownLookingImage(image_t image_id, const Eigen::Vector3d& centre) {
  Image image;
  image.image_id = image_id;
  image.camera_id = 1;
  image.name = "img_" + std::to_string(image_id) + ".png";
  image.cam_from_world.rotation =
      Eigen::Quaterniond(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()));
  image.cam_from_world.translation = -(image.cam_from_world.rotation * centre);
  return image;
}

// Three images 8 m above the seafloor at x = 2, 5 and 8, y = 5: each sees
// 10.24 x 7.68 m, so every x of the seafloor is seen twice or more, for
// 1.16 < y < 8.84.
Reconstruction Survey() {
  Reconstruction survey;
  Camera camera;
  camera.camera_id = 1;
  camera.model_id = CameraModelId::kPinhole;
  camera.width = 640;
  camera.height = 480;
  camera.params = {500.0, 500.0, 320.0, 240.0};
  survey.AddCamera(camera);
  image_t image_id = 1;
  for (const double x : {2.0, 5.0, 8.0}) {
    survey.AddImage(DownLookingImage(image_id++, {x, 5.0, kHeight}));
  }
  return survey;
}

TriangleMesh Shifted(TriangleMesh mesh, const Eigen::Vector3d& offset) {
  for (Eigen::Vector3d& vertex : mesh.vertices) {
    vertex += offset;
  }
  return mesh;
}

MeshComparisonOptions Options() {
  MeshComparisonOptions options;
  options.num_samples = 20000;
  return options;
}

double Area(const TriangleMesh& mesh, size_t t) {
  const Eigen::Vector3i& triangle = mesh.triangles[t];
  return 0.5 *
         (mesh.vertices[triangle[1]] - mesh.vertices[triangle[0]])
             .cross(mesh.vertices[triangle[2]] - mesh.vertices[triangle[0]])
             .norm();
}

Eigen::Vector3d Centroid(const TriangleMesh& mesh, size_t t) {
  const Eigen::Vector3i& triangle = mesh.triangles[t];
  return (mesh.vertices[triangle[0]] + mesh.vertices[triangle[1]] +
          mesh.vertices[triangle[2]]) /
         3.0;
}

// The area of the triangles whose centroid at least `min_views` images of
// the survey see: inside the image by a pinhole projection of our own (the
// seafloor is flat, so nothing occludes).
double ObservedArea(const TriangleMesh& mesh, const Reconstruction& survey,
                    int min_views, double max_range = 0.0) {
  const Camera& camera = survey.Cameras()[0];
  double area = 0.0;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    int views = 0;
    for (const Image& image : survey.Images()) {
      const Eigen::Vector3d point_in_cam =
          image.cam_from_world * Centroid(mesh, t);
      const double x = camera.params[0] * point_in_cam.x() / point_in_cam.z() +
                       camera.params[2];
      const double y = camera.params[1] * point_in_cam.y() / point_in_cam.z() +
                       camera.params[3];
      views += point_in_cam.z() > 0 && x >= 0 && y >= 0 && x < camera.width &&
               y < camera.height &&
               (max_range <= 0.0 || point_in_cam.norm() <= max_range);
    }
    if (views >= min_views) {
      area += Area(mesh, t);
    }
  }
  return area;
}

// Every x is seen twice; y from 1.16 to 8.84: the 30 rows of quads 5 to 34
// and one triangle of each quad of rows 4 and 35 (centroids at 1.17 and
// 8.83 m), 31 rows of 10 x 0.25 m in all.
constexpr double kObservedArea = 31 * 10 * 0.25;

TEST(CompareMeshes, IdenticalMeshesAgreeEverywhere) {
  const TriangleMesh seafloor = Seafloor();
  const MeshComparison comparison =
      CompareMeshes(seafloor, seafloor, Survey(), Options());
  EXPECT_NEAR(comparison.camera_scene_distance, kHeight, 1e-12);
  EXPECT_EQ(comparison.num_samples, 20000u);
  EXPECT_LT(comparison.median, 1e-12);
  EXPECT_LT(comparison.p90, 1e-12);
  EXPECT_LT(comparison.rms, 1e-12);
  EXPECT_LT(std::abs(comparison.mean_signed), 1e-12);
  EXPECT_DOUBLE_EQ(comparison.coverage, 1.0);
  EXPECT_NEAR(comparison.coverage_tolerance, 0.01 * kHeight, 1e-12);
  EXPECT_EQ(comparison.min_views, 2);
  const double expected_observed = ObservedArea(seafloor, Survey(), 2);
  EXPECT_NEAR(expected_observed, kObservedArea, 1e-9);
  EXPECT_NEAR(comparison.observed_area, expected_observed, 1e-9);
  EXPECT_NEAR(comparison.covered_area, expected_observed, 1e-9);
}

TEST(CompareMeshes, OffsetTowardsTheCamerasIsPositive) {
  const TriangleMesh seafloor = Seafloor();
  const Reconstruction survey = Survey();
  const MeshComparison above = CompareMeshes(Shifted(seafloor, {0, 0, 0.01}),
                                             seafloor, survey, Options());
  // Every sample lies 1 cm above the truth.
  EXPECT_NEAR(above.median, 0.01, 1e-12);
  EXPECT_NEAR(above.p90, 0.01, 1e-12);
  EXPECT_NEAR(above.rms, 0.01, 1e-12);
  EXPECT_NEAR(above.mean_signed, 0.01, 1e-12);
  // 1 cm is within the 8 cm coverage tolerance.
  EXPECT_DOUBLE_EQ(above.coverage, 1.0);

  const MeshComparison below = CompareMeshes(Shifted(seafloor, {0, 0, -0.01}),
                                             seafloor, survey, Options());
  EXPECT_NEAR(below.median, 0.01, 1e-12);
  EXPECT_NEAR(below.mean_signed, -0.01, 1e-12);

  // 10 cm is beyond it: nothing is covered.
  const MeshComparison far = CompareMeshes(Shifted(seafloor, {0, 0, 0.1}),
                                           seafloor, survey, Options());
  EXPECT_NEAR(far.median, 0.1, 1e-12);
  EXPECT_EQ(far.coverage, 0.0);
  EXPECT_NEAR(far.observed_area, kObservedArea, 1e-9);
}

TEST(CompareMeshes, HalfTheSurfaceCoversHalf) {
  const TriangleMesh seafloor = Seafloor();
  // The triangles with x < 5 (quad columns 0 to 19). The nearest
  // centroids of the other half lie 8.3 cm from its edge, beyond the 8 cm
  // tolerance, and every column of the seafloor is observed alike: exactly
  // half.
  TriangleMesh half;
  half.vertices = seafloor.vertices;
  for (size_t t = 0; t < seafloor.triangles.size(); ++t) {
    if (Centroid(seafloor, t).x() < 5.0) {
      half.triangles.push_back(seafloor.triangles[t]);
    }
  }
  ASSERT_EQ(half.triangles.size(), seafloor.triangles.size() / 2);
  const MeshComparison comparison =
      CompareMeshes(half, seafloor, Survey(), Options());
  EXPECT_NEAR(comparison.coverage, 0.5, 1e-12);
  EXPECT_NEAR(comparison.observed_area, kObservedArea, 1e-9);
  EXPECT_NEAR(comparison.covered_area, kObservedArea / 2, 1e-9);
  // What there is of it is exact.
  EXPECT_LT(comparison.median, 1e-12);
  EXPECT_LT(comparison.p90, 1e-12);

  // With a tolerance of 20 cm the first column of the other half (centroids
  // 8.3 and 16.7 cm away) counts as covered too: 21 of 40 columns.
  MeshComparisonOptions loose = Options();
  loose.coverage_tolerance = 0.025;
  EXPECT_NEAR(CompareMeshes(half, seafloor, Survey(), loose).coverage,
              21.0 / 40.0, 1e-12);
}

TEST(CompareMeshes, MinViewsSetsTheObservedSurface) {
  const TriangleMesh seafloor = Seafloor();
  MeshComparisonOptions options = Options();
  // Three views see 2.88 <= x < 7.12 only: quad columns 12 to 27 and one
  // triangle of each quad of columns 11 and 28, 17 columns of 31 rows.
  options.min_views = 3;
  const MeshComparison three =
      CompareMeshes(seafloor, seafloor, Survey(), options);
  EXPECT_NEAR(ObservedArea(seafloor, Survey(), 3), 17 * 31 * 0.25 * 0.25, 1e-9);
  EXPECT_NEAR(three.observed_area, 17 * 31 * 0.25 * 0.25, 1e-9);
  EXPECT_EQ(three.min_views, 3);
  // Four views never see anything.
  options.min_views = 4;
  try {
    CompareMeshes(seafloor, seafloor, Survey(), options);
    ADD_FAILURE() << "no error";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("seen by 4 reference images"),
              std::string::npos)
        << error.what();
  }
}

// What the water lets the images see: within 8.5 m of a camera 8 m up, a
// disc of radius 2.87 m under it; seen twice, only where two discs overlap.
TEST(CompareMeshes, MaxRangeLimitsTheObservedSurface) {
  const TriangleMesh seafloor = Seafloor();
  MeshComparisonOptions options = Options();
  options.max_range_m = 8.5;
  const MeshComparison near =
      CompareMeshes(seafloor, seafloor, Survey(), options);
  const double expected = ObservedArea(seafloor, Survey(), 2, 8.5);
  EXPECT_GT(expected, 1.0);
  EXPECT_LT(expected, 0.5 * kObservedArea);
  EXPECT_NEAR(near.observed_area, expected, 1e-9);
  EXPECT_DOUBLE_EQ(near.coverage, 1.0);
  EXPECT_EQ(ToJson(near).at("coverage_max_range").get<double>(), 8.5);
  EXPECT_NE(FormatMeshComparison(near, "mesh.ply")
                .find("within 8.5 m (what the water lets them see)"),
            std::string::npos);
  // Nearer than the floor: nothing is seen.
  options.max_range_m = 7.9;
  ExpectErrorContaining(
      [&] { CompareMeshes(seafloor, seafloor, Survey(), options); },
      "seen by 2 reference images");
  options.max_range_m = -1.0;
  ExpectErrorContaining([&] { options.Check(); }, "max_range_m");
}

TEST(CompareMeshes, CameraSceneDistanceRunsAlongTheOpticalAxis) {
  Reconstruction survey = Survey();
  // Heights 7, 8 (tilted by 30 degrees about x) and 10: along their axes
  // 7, 8 / cos(30 deg) = 9.24 and 10; the median is the tilted one.
  survey.Images()[0] = DownLookingImage(1, {2.0, 5.0, 7.0});
  survey.Images()[2] = DownLookingImage(3, {8.0, 5.0, 10.0});
  Image& tilted = survey.Images()[1];
  const Eigen::Vector3d centre(5.0, 5.0, kHeight);
  tilted.cam_from_world.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(
                                       M_PI / 6, Eigen::Vector3d::UnitX())) *
                                   tilted.cam_from_world.rotation;
  tilted.cam_from_world.translation =
      -(tilted.cam_from_world.rotation * centre);
  const TriangleMesh seafloor = Seafloor();
  const MeshComparison comparison =
      CompareMeshes(seafloor, seafloor, survey, Options());
  EXPECT_NEAR(comparison.camera_scene_distance, kHeight / std::cos(M_PI / 6),
              1e-9);
  EXPECT_NEAR(comparison.coverage_tolerance,
              0.01 * kHeight / std::cos(M_PI / 6), 1e-11);
}

TEST(TransformMesh, AppliesTheSimilarity) {
  Sim3d b_from_a;
  b_from_a.scale = 2.5;
  b_from_a.rotation = Eigen::Quaterniond(
      Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, -2, 0.5).normalized()));
  b_from_a.translation = Eigen::Vector3d(100.0, -20.0, 3.0);
  const TriangleMesh in_a = Seafloor();
  const TriangleMesh in_b = TransformMesh(b_from_a, in_a);
  ASSERT_EQ(in_b.vertices.size(), in_a.vertices.size());
  EXPECT_EQ(in_b.triangles, in_a.triangles);
  const Eigen::Matrix3d rotation = b_from_a.rotation.toRotationMatrix();
  for (size_t i = 0; i < in_a.vertices.size(); ++i) {
    const Eigen::Vector3d expected =
        2.5 * (rotation * in_a.vertices[i]) + b_from_a.translation;
    ASSERT_LT((in_b.vertices[i] - expected).norm(), 1e-12) << i;
  }

  // A reconstruction in another frame, brought into the reference's.
  const TriangleMesh reconstruction_in_a =
      TransformMesh(b_from_a.Inverse(), Shifted(in_a, {0, 0, 0.02}));
  const MeshComparison comparison = CompareMeshes(
      TransformMesh(b_from_a, reconstruction_in_a), in_a, Survey(), Options());
  EXPECT_NEAR(comparison.median, 0.02, 1e-12);
  EXPECT_NEAR(comparison.mean_signed, 0.02, 1e-12);
}

TEST(CompareMeshes, ResultDoesNotDependOnThreads) {
  const TriangleMesh seafloor = Seafloor();
  // A wavy reconstruction, so that the distances differ from sample to
  // sample.
  TriangleMesh wavy = seafloor;
  for (Eigen::Vector3d& vertex : wavy.vertices) {
    vertex.z() = 0.15 * std::sin(3.0 * vertex.x()) * std::cos(2.0 * vertex.y());
  }
  MeshComparison one_thread;
  MeshComparison two_threads;
  tbb::task_arena(1).execute(
      [&] { one_thread = CompareMeshes(wavy, seafloor, Survey(), Options()); });
  tbb::task_arena(2).execute([&] {
    two_threads = CompareMeshes(wavy, seafloor, Survey(), Options());
  });
  EXPECT_EQ(ToJson(one_thread).dump(), ToJson(two_threads).dump());
  EXPECT_GT(one_thread.median, 0.01);
  EXPECT_LT(one_thread.median, 0.1);
  EXPECT_GT(one_thread.coverage, 0.0);
  EXPECT_LT(one_thread.coverage, 1.0);
  // Another seed draws other samples.
  MeshComparisonOptions reseeded = Options();
  reseeded.seed = 2;
  EXPECT_NE(CompareMeshes(wavy, seafloor, Survey(), reseeded).median,
            one_thread.median);
}

TEST(CompareMeshes, ToJsonReportsEveryField) {
  const TriangleMesh seafloor = Seafloor();
  const MeshComparison comparison = CompareMeshes(
      Shifted(seafloor, {0, 0, 0.01}), seafloor, Survey(), Options());
  const nlohmann::json json = ToJson(comparison);
  EXPECT_DOUBLE_EQ(json.at("camera_scene_distance").get<double>(), kHeight);
  EXPECT_DOUBLE_EQ(json.at("median_distance").get<double>(), comparison.median);
  EXPECT_NEAR(json.at("median_over_camera_scene_distance").get<double>(),
              0.01 / kHeight, 1e-12);
  EXPECT_DOUBLE_EQ(json.at("coverage").get<double>(), 1.0);
  EXPECT_EQ(json.at("coverage_min_views").get<int>(), 2);
  EXPECT_EQ(json.at("num_samples").get<size_t>(), 20000u);
}

TEST(FormatMeshComparison, PrintsTheFiguresOfTheDenseSurface) {
  MeshComparison comparison;
  comparison.camera_scene_distance = 2.2;
  comparison.num_samples = 200000;
  comparison.median = 0.0024;
  comparison.p90 = 0.006;
  comparison.rms = 0.004;
  comparison.mean_signed = -0.0005;
  comparison.observed_area = 30.5;
  comparison.coverage = 0.94;
  comparison.coverage_tolerance = 0.022;
  comparison.min_views = 2;
  EXPECT_EQ(FormatMeshComparison(comparison, "mesh.ply"),
            "Dense surface: mesh.ply (after the alignment)\n"
            "  camera-scene distance (median along the optical axes): 2.2 m\n"
            "  distance to the reference surface over 200000 samples: median "
            "0.0024 m (0.109 % of the camera-scene distance), 90 % 0.006 m, "
            "RMS 0.004 m, signed mean -0.0005 m\n"
            "  coverage: 94.00 % of the 30.5 m^2 seen by >= 2 reference "
            "images lie within 0.022 m of the dense surface\n");
}

TEST(CompareMeshes, InvalidInputsThrow) {
  const TriangleMesh seafloor = Seafloor();
  ExpectErrorContaining(
      [&] { CompareMeshes(TriangleMesh(), seafloor, Survey(), Options()); },
      "no triangles");
  // Cameras looking up, away from the seafloor.
  Reconstruction looking_up = Survey();
  for (Image& image : looking_up.Images()) {
    const Eigen::Vector3d centre = image.ProjectionCenter();
    image.cam_from_world.rotation = Eigen::Quaterniond::Identity();
    image.cam_from_world.translation = -centre;
  }
  ExpectErrorContaining(
      [&] { CompareMeshes(seafloor, seafloor, looking_up, Options()); },
      "no reference image looks at the reference surface");
  MeshComparisonOptions options = Options();
  options.num_samples = 0;
  ExpectErrorContaining(
      [&] { CompareMeshes(seafloor, seafloor, Survey(), options); },
      "num_samples");
  options = Options();
  options.min_views = 0;
  ExpectErrorContaining([&] { options.Check(); }, "min_views");
  options = Options();
  options.coverage_tolerance = 0.0;
  ExpectErrorContaining([&] { options.Check(); }, "coverage_tolerance");
}

}  // namespace
}  // namespace uw
