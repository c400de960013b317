#include "colmap_plugins/align/model_comparison.h"

#include <gtest/gtest.h>

#include <cmath>

#include "colmap_plugins/align/sim3.h"
#include "common/util/error.h"

namespace uw {
namespace {

// The ground: z = h(x, y) over [-5, 45] x [-5, 5].
double Height(double x, double y) {
  return 0.2 * std::sin(0.5 * x) * std::cos(0.8 * y);
}

struct Scene {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3i> triangles;
  Reconstruction truth;
};

// 41 down-looking cameras 1 m apart along x, 3 m above the ground, each
// seeing the points of the ground below it.
Scene MakeScene() {
  Scene scene;
  const int nx = 200;
  const int ny = 40;
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      const double x = -5.0 + 50.0 * i / nx;
      const double y = -5.0 + 10.0 * j / ny;
      scene.vertices.emplace_back(x, y, Height(x, y));
    }
  }
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const int a = j * (nx + 1) + i;
      scene.triangles.emplace_back(a, a + 1, a + nx + 2);
      scene.triangles.emplace_back(a, a + nx + 2, a + nx + 1);
    }
  }
  Camera camera;
  camera.camera_id = 1;
  camera.model_id = CameraModelId::kSimplePinhole;
  camera.width = 1000;
  camera.height = 1000;
  camera.params = {500.0, 500.0, 500.0};
  scene.truth.AddCamera(camera);
  // Looking down (-z), image x along world x.
  const Eigen::Quaterniond cam_from_world_rotation(
      Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()));
  for (int k = 0; k <= 40; ++k) {
    Image image;
    image.image_id = k + 1;
    image.camera_id = 1;
    char name[16];
    std::snprintf(name, sizeof(name), "%05d.png", k);
    image.name = name;
    const Eigen::Vector3d centre(k, 0.3 * std::sin(0.4 * k),
                                 3.0 + 0.1 * std::cos(0.3 * k));
    image.cam_from_world.rotation = cam_from_world_rotation;
    image.cam_from_world.translation = -(cam_from_world_rotation * centre);
    scene.truth.AddImage(image);
  }
  point3D_t point3D_id = 1;
  for (double x = -1.0; x <= 41.0; x += 0.1) {
    for (double y = -1.5; y <= 1.5; y += 0.25) {
      Point3D point;
      point.point3D_id = point3D_id++;
      point.xyz = Eigen::Vector3d(x, y, Height(x, y));
      point.error = 0.5;
      const int nearest = std::clamp(static_cast<int>(std::lround(x)), 0, 39);
      point.track = {{static_cast<image_t>(nearest + 1), 0},
                     {static_cast<image_t>(nearest + 2), 0}};
      scene.truth.AddPoint3D(point);
    }
  }
  return scene;
}

TEST(CompareModels, ATransformedCopyOfTheTruthMatchesIt) {
  const Scene scene = MakeScene();
  const MeshDistance surface(scene.vertices, scene.triangles);
  Reconstruction model = scene.truth;
  // A point 1 m above the surface, and one with a large error (left out).
  model.Points3D()[0].xyz += Eigen::Vector3d(0, 0, 1.0);
  model.Points3D()[1].error = 3.0;
  model.Points3D()[1].xyz += Eigen::Vector3d(0, 0, 10.0);
  Sim3d model_from_truth;
  model_from_truth.scale = 0.37;
  model_from_truth.rotation = Eigen::Quaterniond(
      Eigen::AngleAxisd(1.1, Eigen::Vector3d(1, 2, 3).normalized()));
  model_from_truth.translation = Eigen::Vector3d(4, -2, 7);
  TransformReconstruction(model_from_truth, &model);

  const ModelComparison comparison =
      CompareModels(model, scene.truth, &surface, {});
  EXPECT_EQ(comparison.cameras.size(), 41u);
  EXPECT_LT(comparison.camera_rmse_m, 1e-9);
  EXPECT_LT(comparison.rotation_max_deg, 1e-6);
  EXPECT_NEAR(comparison.alignment.b_from_a.scale, 1 / 0.37, 1e-9);
  EXPECT_NEAR(comparison.axis.length, 40.0, 1e-3);
  ASSERT_EQ(comparison.segments.size(), 6u);
  for (const SegmentScale& segment : comparison.segments) {
    EXPECT_NEAR(segment.scale_3d, 1.0, 1e-9);
    EXPECT_NEAR(segment.scale_along_track, 1.0, 1e-9);
    EXPECT_NEAR(segment.view_tilt_deg, 0.0, 1e-6);
  }
  EXPECT_NEAR(comparison.distance_ratios.median_ratio, 0.37, 1e-9);
  ASSERT_TRUE(comparison.surface.has_value());
  const SurfaceDeviation& deviation = *comparison.surface;
  EXPECT_EQ(deviation.num_points_used, deviation.num_points - 1);
  // 1 m up is at most 1 m from a surface of gentle slope; the other points
  // lie on the smooth ground, within the facets' chord error (< 1 mm).
  EXPECT_NEAR(deviation.max_abs_m, 1.0, 0.02);
  EXPECT_LT(deviation.median_abs_m, 1e-3);
  EXPECT_LT(deviation.p95_abs_m, 2e-3);
  EXPECT_LT(std::abs(deviation.dome.sagitta_m), 1e-3);
  EXPECT_EQ(deviation.bins.size(), 12u);

  const nlohmann::json json = ToJson(comparison);
  EXPECT_EQ(json.at("num_common_images").get<size_t>(), 41u);
  EXPECT_EQ(json.at("segments").size(), 6u);
  EXPECT_TRUE(json.at("surface").at("dome").at("valid").get<bool>());
}

TEST(CompareModels, ADomedModelShowsItsSagitta) {
  const Scene scene = MakeScene();
  const MeshDistance surface(scene.vertices, scene.triangles);
  Reconstruction model = scene.truth;
  // Raise the model towards the cameras by c (x − 20)² − ... : the ends
  // drop 0.4 m below the middle.
  const auto lift = [](const Eigen::Vector3d& p) {
    return -0.001 * (p.x() - 20.0) * (p.x() - 20.0);
  };
  for (Point3D& point : model.Points3D()) point.xyz.z() += lift(point.xyz);
  for (Image& image : model.Images()) {
    const Eigen::Vector3d centre = image.ProjectionCenter();
    image.cam_from_world.translation =
        -(image.cam_from_world.rotation *
          (centre + Eigen::Vector3d(0, 0, lift(centre))));
  }
  const ModelComparison comparison =
      CompareModels(model, scene.truth, &surface, {});
  ASSERT_TRUE(comparison.surface.has_value());
  const DomeFit& dome = comparison.surface->dome;
  std::cout << "[ figures ] domed model: sagitta " << dome.sagitta_m << " m ("
            << dome.sagitta_percent << " %), camera RMSE "
            << comparison.camera_rmse_m << " m\n";
  ASSERT_TRUE(dome.valid);
  // The similarity tilts and lifts the parabola but cannot remove it:
  // sagitta -c L² / 4 = -0.4 m with L = 40 m.
  EXPECT_NEAR(dome.sagitta_m, -0.4, 0.02);
  EXPECT_GT(comparison.segments.front().scale_along_track,
            comparison.segments[2].scale_along_track);
}

// A model in the reference's frame, off by a constant offset: without
// alignment the offset is the error; a similarity removes it.
TEST(CompareModels, WithoutAlignmentMeasuresAbsoluteErrors) {
  const Scene scene = MakeScene();
  Reconstruction model = scene.truth;
  Sim3d shifted;
  shifted.translation = Eigen::Vector3d(0.3, 0.0, -0.4);
  TransformReconstruction(shifted, &model);
  ModelComparisonOptions options;
  options.align = false;
  const ModelComparison absolute =
      CompareModels(model, scene.truth, nullptr, options);
  EXPECT_FALSE(absolute.aligned);
  EXPECT_NEAR(absolute.camera_rmse_m, 0.5, 1e-12);
  EXPECT_NEAR(absolute.cameras[7].position_error_m.x(), 0.3, 1e-12);
  EXPECT_EQ(absolute.alignment.b_from_a.scale, 1.0);
  options.align = true;
  options.alignment.estimate_scale = false;
  EXPECT_LT(CompareModels(model, scene.truth, nullptr, options).camera_rmse_m,
            1e-12);
}

TEST(CompareModels, NeedsThreeCommonImages) {
  const Scene scene = MakeScene();
  Reconstruction model;
  model.AddCamera(scene.truth.Cameras()[0]);
  for (int k = 0; k < 2; ++k) model.AddImage(scene.truth.Images()[k]);
  Image renamed = scene.truth.Images()[2];
  renamed.name = "images/" + renamed.name;
  model.AddImage(renamed);
  try {
    CompareModels(model, scene.truth, nullptr, {});
    ADD_FAILURE() << "no error";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("2 image names in common"),
              std::string::npos)
        << error.what();
  }
}

// The printout's columns stay where scripts and readers expect them.
TEST(FormatModelComparison, PrintsEveryFigureInItsColumn) {
  ModelComparison comparison;
  comparison.num_model_images = 10;
  comparison.num_reference_images = 11;
  comparison.missing_images = {"img11.png"};
  comparison.cameras.resize(10);
  comparison.alignment.b_from_a.scale = 0.5;
  comparison.alignment.num_inliers = 10;
  comparison.camera_rmse_m = 0.01;
  comparison.camera_max_error_m = 0.02;
  comparison.reference_extent_m = 20.0;
  comparison.rotation_rmse_deg = 0.1;
  comparison.rotation_max_deg = 0.25;
  comparison.axis.length = 18.5;
  comparison.axis.direction = Eigen::Vector3d(1, 0, 0);
  SegmentScale segment;
  segment.begin = 0.0;
  segment.end = 9.25;
  segment.num_images = 5;
  segment.scale_3d = 1.00012;
  segment.scale_along_track = 0.99987;
  segment.view_tilt_deg = 2.5;
  comparison.segments = {segment};
  comparison.distance_ratios.num_pairs = 45;
  comparison.distance_ratios.median_ratio = 1.0;
  comparison.distance_ratios.max_abs_deviation = 0.002;
  comparison.distance_ratios.p95_abs_deviation = 0.001;
  SurfaceDeviation surface;
  surface.num_points = 100;
  surface.num_points_used = 90;
  surface.rms_m = 0.003;
  surface.bins.push_back({0.0, 18.5, 90, -0.001});
  surface.dome.valid = false;
  comparison.surface = surface;
  ModelComparisonOptions options;
  EXPECT_EQ(
      FormatModelComparison(comparison, "mesh.ply", options),
      "Images: model 10, reference 11, common 10 (reference images missing "
      "from the model: 1, e.g. img11.png)\n"
      "Alignment reference_from_model (similarity, least squares): scale "
      "0.5, 10 of 10 inliers\n"
      "Camera centres: RMSE 0.01 m = 0.0500 % of the 20 m extent, max 0.02 "
      "m\n"
      "Camera rotations: RMS 0.1 deg, max 0.25 deg\n"
      "Track: 18.5 m along (1.0000, 0.0000, 0.0000)\n"
      "segment      from_m       to_m  images   scale_3d  scale_along   "
      "tilt_deg\n"
      "A             0.000      9.250       5    1.00012      0.99987      "
      "2.500\n"
      "Camera distance ratios model/reference (45 pairs): median 1, max "
      "|r-1| 0.002, 95 % |r-1| 0.001\n"
      "Surface mesh.ply: 90 of 100 points (error <= 2 px), signed distance "
      "(+ towards the cameras): RMS 0.003 m, mean 0 m, median 0 m, median "
      "|d| 0 m, 95 % |d| 0 m, max |d| 0 m\n"
      "bin          from_m       to_m   points     median_m\n"
      "1             0.000     18.500       90    -0.001000\n"
      "Dome fit: fewer than 3 bins with 10 points\n");
  comparison.aligned = false;
  comparison.surface.reset();
  EXPECT_NE(FormatModelComparison(comparison, "", options)
                .find("Alignment: none (the model is compared where it is)\n"),
            std::string::npos);
}

}  // namespace
}  // namespace uw
