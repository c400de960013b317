#include "sim/observe.h"

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <set>

#include <gtest/gtest.h>

#include "colmap_plugins/scene/model_io.h"
#include "common/mesh/test_meshes.h"
#include "common/util/error.h"
#include "common/util/file.h"
#include "sim/generate.h"
#include "sim/test_sim_config.h"

namespace uw::sim {
namespace {

namespace fs = std::filesystem;

// A floor z = 0 over [-3, 3]^2 and, 1 m above it, a plate over
// [-0.5, 0.5]^2 that hides part of the floor from each camera.
constexpr double kPlateHalfSize = 0.5;
constexpr double kPlateHeight = 1.0;
TriangleMesh FloorAndPlate() {
  TriangleMesh mesh;
  AddGrid({-3, -3, 0}, {6, 0, 0}, {0, 6, 0}, 12, 12, &mesh);
  AddGrid({-kPlateHalfSize, -kPlateHalfSize, kPlateHeight},
          {2 * kPlateHalfSize, 0, 0}, {0, 2 * kPlateHalfSize, 0}, 2, 2, &mesh);
  return mesh;
}

// Five cameras looking straight down from 3 m, 0.6 m apart along x.
Reconstruction DownLookingCameras() {
  Reconstruction model;
  Camera camera;
  camera.camera_id = 1;
  camera.model_id = CameraModelId::kSimpleRadial;
  camera.width = 320;
  camera.height = 240;
  camera.params = {200.0, 160.0, 120.0, -0.05};
  model.AddCamera(camera);
  Eigen::Matrix3d cam_from_world;
  cam_from_world << 1, 0, 0, 0, -1, 0, 0, 0, -1;
  for (int k = 0; k < 5; ++k) {
    Image image;
    image.image_id = static_cast<image_t>(10 + k);
    image.camera_id = 1;
    image.name = "img" + std::to_string(k) + ".png";
    image.cam_from_world.rotation = Eigen::Quaterniond(cam_from_world);
    const Eigen::Vector3d centre(-1.2 + 0.6 * k, 0.1, 3.0);
    image.cam_from_world.translation = -(cam_from_world * centre);
    model.AddImage(image);
  }
  return model;
}

Eigen::Vector2d Reprojection(const Reconstruction& model, const Point3D& point,
                             const TrackElement& element) {
  const Image& image = *model.FindImage(element.image_id);
  return model.FindCamera(image.camera_id)
      ->ImgFromCam(image.cam_from_world * point.xyz);
}

// Whether the segment from `centre` to a floor point crosses the plate
// (margin > 0: by more than the margin; < 0: or passes within it).
bool CrossesPlate(const Eigen::Vector3d& centre, const Eigen::Vector3d& point,
                  double margin) {
  if (point.z() > 0.5 * kPlateHeight) return false;  // on the plate
  const double s = (centre.z() - kPlateHeight) / (centre.z() - point.z());
  const Eigen::Vector3d crossing = centre + s * (point - centre);
  return std::abs(crossing.x()) < kPlateHalfSize - margin &&
         std::abs(crossing.y()) < kPlateHalfSize - margin;
}

TEST(Observe, ZeroNoiseObservationsAreTheTrueProjections) {
  const Reconstruction truth = DownLookingCameras();
  ObserveOptions options;
  options.pixel_sigma = 0.0;
  options.num_points = 3000;
  ObserveSummary summary;
  const Reconstruction model =
      ObserveModel(truth, FloorAndPlate(), options, &summary);
  model.Check("observed model");
  ASSERT_EQ(model.Points3D().size(), 3000u);
  EXPECT_EQ(summary.num_points, 3000u);
  EXPECT_GT(summary.num_candidates, summary.num_points);
  ASSERT_EQ(model.Images().size(), truth.Images().size());
  for (size_t i = 0; i < truth.Images().size(); ++i) {
    EXPECT_EQ(model.Images()[i].image_id, truth.Images()[i].image_id);
    EXPECT_EQ(model.Images()[i].name, truth.Images()[i].name);
  }
  double max_error = 0.0;
  size_t observations = 0;
  for (const Point3D& point : model.Points3D()) {
    EXPECT_GE(point.track.size(), 2u);
    EXPECT_LT(point.error, 1e-9);
    for (const TrackElement& element : point.track) {
      const Point2D& point2D =
          model.FindImage(element.image_id)->points2D[element.point2D_idx];
      EXPECT_EQ(point2D.point3D_id, point.point3D_id);
      max_error = std::max(
          max_error, (Reprojection(model, point, element) - point2D.xy).norm());
      ++observations;
    }
  }
  EXPECT_EQ(observations, summary.num_observations);
  std::cout << "[ figures ] observe, zero noise: " << summary.num_points
            << " points from " << summary.num_candidates << " candidates, "
            << observations << " observations, max reprojection error "
            << max_error << " px" << std::endl;
  EXPECT_LT(max_error, 1e-9);
}

TEST(Observe, PixelNoiseHasTheConfiguredSigma) {
  ObserveOptions options;
  options.pixel_sigma = 0.7;
  options.num_points = 5000;
  const Reconstruction model =
      ObserveModel(DownLookingCameras(), FloorAndPlate(), options);
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  Eigen::Vector2d sum_squares = Eigen::Vector2d::Zero();
  size_t n = 0;
  for (const Point3D& point : model.Points3D()) {
    for (const TrackElement& element : point.track) {
      const Eigen::Vector2d residual =
          model.FindImage(element.image_id)->points2D[element.point2D_idx].xy -
          Reprojection(model, point, element);
      sum += residual;
      sum_squares += residual.cwiseProduct(residual);
      ++n;
    }
  }
  const Eigen::Vector2d sigma = (sum_squares / n).cwiseSqrt();
  std::cout << "[ figures ] observe, pixel_sigma 0.7: measured " << sigma.x()
            << ", " << sigma.y() << " px over " << n << " observations"
            << std::endl;
  // > 10000 samples per axis: the sigma is known to ~1 %.
  ASSERT_GT(n, 10000u);
  EXPECT_NEAR(sigma.x(), 0.7, 0.03);
  EXPECT_NEAR(sigma.y(), 0.7, 0.03);
  EXPECT_LT((sum / n).norm(), 0.03);
}

TEST(Observe, OccludedPointsAreNotObserved) {
  const Reconstruction truth = DownLookingCameras();
  ObserveOptions options;
  options.num_points = 4000;
  const Reconstruction model = ObserveModel(truth, FloorAndPlate(), options);
  size_t on_plate = 0;
  size_t under_plate = 0;
  for (const Point3D& point : model.Points3D()) {
    if (point.xyz.z() > 0.5 * kPlateHeight) ++on_plate;
    if (point.xyz.z() < 0.5 * kPlateHeight &&
        point.xyz.head<2>().cwiseAbs().maxCoeff() < kPlateHalfSize) {
      ++under_plate;  // only oblique views see under the plate
    }
    std::set<image_t> observers;
    for (const TrackElement& element : point.track) {
      observers.insert(element.image_id);
      const Image& image = *model.FindImage(element.image_id);
      EXPECT_FALSE(CrossesPlate(image.ProjectionCenter(), point.xyz, 1e-6))
          << "point " << point.point3D_id << " seen by " << image.name
          << " through the plate";
    }
    // Every image that has the point in view and a clear line of sight
    // observes it.
    for (const Image& image : truth.Images()) {
      if (observers.count(image.image_id)) continue;
      const Eigen::Vector3d in_cam = image.cam_from_world * point.xyz;
      const Eigen::Vector2d pixel = truth.FindCamera(1)->ImgFromCam(in_cam);
      const bool inside = pixel.x() > 1e-6 && pixel.y() > 1e-6 &&
                          pixel.x() < 320 - 1e-6 && pixel.y() < 240 - 1e-6;
      EXPECT_FALSE(inside &&
                   !CrossesPlate(image.ProjectionCenter(), point.xyz, -1e-6))
          << "point " << point.point3D_id << " not observed by " << image.name;
    }
  }
  std::cout << "[ figures ] observe, occlusion: " << on_plate
            << " points on the plate, " << under_plate
            << " on the floor under it (seen from the side)" << std::endl;
  EXPECT_GT(on_plate, 50u);
  EXPECT_GT(under_plate, 10u);
}

TEST(Observe, SameSeedGivesTheSameModel) {
  const Reconstruction truth = DownLookingCameras();
  const TriangleMesh mesh = FloorAndPlate();
  ObserveOptions options;
  options.num_points = 500;
  options.seed = 7;
  const Reconstruction one = ObserveModel(truth, mesh, options);
  const Reconstruction two = ObserveModel(truth, mesh, options);
  options.seed = 8;
  const Reconstruction other = ObserveModel(truth, mesh, options);
  EXPECT_EQ(ImagesText(one), ImagesText(two));
  EXPECT_EQ(Points3DText(one), Points3DText(two));
  EXPECT_NE(Points3DText(one), Points3DText(other));
  EXPECT_NE(ImagesText(one), ImagesText(other));
}

TEST(Observe, PerturbedModelIsTheTruthUnderTheReportedSimilarity) {
  const Reconstruction truth = DownLookingCameras();
  const TriangleMesh mesh = FloorAndPlate();
  ObserveOptions options;
  options.num_points = 500;
  const Reconstruction exact = ObserveModel(truth, mesh, options);
  options.init = ObserveInit::kPerturbed;
  options.perturb_rotation_deg = 0.0;
  options.perturb_position_m = 0.0;
  ObserveSummary summary;
  const Reconstruction moved = ObserveModel(truth, mesh, options, &summary);
  const Sim3d& model_from_world = summary.model_from_world;
  EXPECT_GE(model_from_world.scale, 0.3);
  EXPECT_LE(model_from_world.scale, 3.0);
  ASSERT_EQ(moved.Points3D().size(), exact.Points3D().size());
  for (size_t i = 0; i < exact.Points3D().size(); ++i) {
    EXPECT_LT(
        (model_from_world * exact.Points3D()[i].xyz - moved.Points3D()[i].xyz)
            .norm(),
        1e-9);
    // The observations do not change, and still fit.
    EXPECT_LT(moved.Points3D()[i].error, 1e-9 + exact.Points3D()[i].error);
  }
  for (size_t i = 0; i < exact.Images().size(); ++i) {
    EXPECT_EQ(moved.Images()[i].name, exact.Images()[i].name);
    EXPECT_LT((model_from_world * exact.Images()[i].ProjectionCenter() -
               moved.Images()[i].ProjectionCenter())
                  .norm(),
              1e-9);
    EXPECT_EQ(moved.Images()[i].points2D.size(),
              exact.Images()[i].points2D.size());
  }

  // With pose noise the cameras move by about perturb_position_m.
  options.perturb_position_m = 0.05;
  options.perturb_rotation_deg = 0.5;
  const Reconstruction noisy = ObserveModel(truth, mesh, options, &summary);
  double sum_squares = 0.0;
  double error_sum = 0.0;
  const Sim3d world_from_model = summary.model_from_world.Inverse();
  for (size_t i = 0; i < exact.Images().size(); ++i) {
    sum_squares += (world_from_model * noisy.Images()[i].ProjectionCenter() -
                    exact.Images()[i].ProjectionCenter())
                       .squaredNorm();
  }
  for (const Point3D& point : noisy.Points3D()) error_sum += point.error;
  const double rms = std::sqrt(sum_squares / (3 * exact.Images().size()));
  std::cout << "[ figures ] observe, perturbed: scale "
            << summary.model_from_world.scale << ", camera centre noise " << rms
            << " m RMS per axis, mean track error "
            << error_sum / noisy.Points3D().size() << " px" << std::endl;
  EXPECT_GT(rms, 0.01);
  EXPECT_LT(rms, 0.15);
}

// Five cameras 1 m above a floor, 0.6 m apart (footprints 1.6 m wide), and
// a sixth 1.2 m past the last: only the fifth shares its view, so none of
// its points is seen three times and no mapper would register it.
TEST(Observe, DropsImagesAMapperWouldNotRegister) {
  Reconstruction truth = DownLookingCameras();
  for (Image& image : truth.Images()) {
    image.cam_from_world.translation =
        -(image.cam_from_world.rotation *
          (image.ProjectionCenter() - Eigen::Vector3d(0, 0, 2.0)));
  }
  Image far = truth.Images().back();
  far.image_id = 15;
  far.name = "img5.png";
  far.cam_from_world.translation =
      -(far.cam_from_world.rotation * Eigen::Vector3d(2.4, 0.1, 1.0));
  truth.AddImage(far);
  TriangleMesh floor;
  AddGrid({-3, -3, 0}, {6, 0, 0}, {0, 6, 0}, 12, 12, &floor);
  ObserveOptions options;
  options.num_points = 2000;
  const Reconstruction all = ObserveModel(truth, floor, options);
  ASSERT_NE(all.FindImage(15), nullptr);
  EXPECT_GT(all.FindImage(15)->points2D.size(), 20u);

  options.min_registration_points = 20;
  ObserveSummary summary;
  const Reconstruction kept = ObserveModel(truth, floor, options, &summary);
  EXPECT_EQ(summary.dropped_images, std::vector<std::string>{"img5.png"});
  EXPECT_EQ(kept.FindImage(15), nullptr);
  EXPECT_EQ(kept.Images().size(), 5u);
  EXPECT_EQ(summary.num_points, kept.Points3D().size());
  EXPECT_LT(kept.Points3D().size(), all.Points3D().size());
  size_t observations = 0;
  std::map<image_t, int> seen_thrice;
  for (const Point3D& point : kept.Points3D()) {
    ASSERT_GE(point.track.size(), 2u);
    observations += point.track.size();
    const Point3D& original = *all.FindPoint3D(point.point3D_id);
    EXPECT_EQ(point.xyz, original.xyz);
    for (const TrackElement& element : point.track) {
      if (point.track.size() >= 3) ++seen_thrice[element.image_id];
      const Image& image = *kept.FindImage(element.image_id);
      const Point2D& observed = image.points2D.at(element.point2D_idx);
      EXPECT_EQ(observed.point3D_id, point.point3D_id);
      // The same noisy pixel as without the filter.
      bool found = false;
      for (const Point2D& before : all.FindImage(element.image_id)->points2D) {
        found = found || (before.point3D_id == point.point3D_id &&
                          before.xy == observed.xy);
      }
      EXPECT_TRUE(found) << point.point3D_id;
    }
  }
  EXPECT_EQ(summary.num_observations, observations);
  for (const Image& image : kept.Images()) {
    EXPECT_GE(seen_thrice[image.image_id], 20) << image.name;
  }
}

TEST(Observe, RejectsBadOptions) {
  ObserveOptions options;
  options.pixel_sigma = -1.0;
  EXPECT_THROW(options.Check(), Error);
  options = ObserveOptions();
  options.num_points = 0;
  EXPECT_THROW(options.Check(), Error);
  options = ObserveOptions();
  options.min_registration_points = -1;
  EXPECT_THROW(options.Check(), Error);
  EXPECT_THROW(ObserveInitFromName("navigation"), Error);
  EXPECT_EQ(ObserveInitFromName("perturbed"), ObserveInit::kPerturbed);
}

// A generated multi-dive survey with a stereo rig: the model keeps every
// image of both cameras, with truth/'s ids and names.
TEST(ObserveSimulation, WritesTheModelOfARigOverTwoDives) {
  SimConfig config = SmallSimConfig();
  config.survey = SurveyKind::kMultiDive;
  config.lasers.every_nth_image = 0;
  config.render.sensor.supersampling = 1;
  RigCameraOptions second;
  second.camera = config.camera;
  second.cam_from_rig.translation = Eigen::Vector3d(-0.3, 0, 0);
  second.time_offset_s = 0.03;
  config.rig.cameras = {second};
  const fs::path dir =
      fs::temp_directory_path() / ("uw_observe_" + std::to_string(getpid()));
  fs::remove_all(dir);
  Generate(config, dir / "sim");
  ObserveOptions options;
  options.num_points = 2000;
  const ObserveSummary summary =
      ObserveSimulation(dir / "sim", dir / "model", options);
  const Reconstruction truth = ReadModel(dir / "sim" / "truth");
  const Reconstruction model = ReadModel(dir / "model");
  EXPECT_EQ(summary.num_points, 2000u);
  EXPECT_EQ(model.Points3D().size(), 2000u);
  ASSERT_EQ(model.Images().size(), truth.Images().size());
  size_t cam2_observations = 0;
  for (size_t i = 0; i < truth.Images().size(); ++i) {
    EXPECT_EQ(model.Images()[i].image_id, truth.Images()[i].image_id);
    EXPECT_EQ(model.Images()[i].name, truth.Images()[i].name);
    if (model.Images()[i].camera_id == 2) {
      cam2_observations += model.Images()[i].points2D.size();
    }
  }
  std::cout << "[ figures ] observe, rig over 2 dives: "
            << truth.Images().size() << " images, " << summary.num_points
            << " points, " << summary.num_observations << " observations ("
            << cam2_observations << " by camera 2)" << std::endl;
  EXPECT_GT(cam2_observations, 1000u);
  // Never into a folder in use; nothing written when the input is missing.
  EXPECT_THROW(ObserveSimulation(dir / "sim", dir / "model", options), Error);
  EXPECT_THROW(ObserveSimulation(dir / "missing", dir / "other", options),
               Error);
  EXPECT_FALSE(fs::exists(dir / "other"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace uw::sim
