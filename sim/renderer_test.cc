#include "sim/renderer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "common/mesh/test_meshes.h"
#include "common/util/error.h"

namespace uw::sim {
namespace {

// The plane z = distance, facing a camera at the origin (-z), 100 m wide.
TriangleMesh FacingPlane(double distance) {
  TriangleMesh mesh;
  AddGrid({-50, -50, distance}, {0, 100, 0}, {100, 0, 0}, 4, 4, &mesh);
  return mesh;
}

// An axis-aligned box with outward normals.
void AddBox(const Eigen::Vector3d& lower, const Eigen::Vector3d& upper,
            TriangleMesh* mesh) {
  const Eigen::Vector3d size = upper - lower;
  const Eigen::Vector3d x(size.x(), 0, 0);
  const Eigen::Vector3d y(0, size.y(), 0);
  const Eigen::Vector3d z(0, 0, size.z());
  AddGrid(lower, y, x, 1, 1, mesh);
  AddGrid(lower + z, x, y, 1, 1, mesh);
  AddGrid(lower, x, z, 1, 1, mesh);
  AddGrid(lower + y, z, x, 1, 1, mesh);
  AddGrid(lower, z, y, 1, 1, mesh);
  AddGrid(lower + x, y, z, 1, 1, mesh);
}

// Rolling hills with bumps, 20 m x 20 m around the origin, facing up.
TriangleMesh BumpyFloor(int cells) {
  TriangleMesh mesh;
  AddGrid({-10, -10, 0}, {20, 0, 0}, {0, 20, 0}, cells, cells, &mesh);
  for (Eigen::Vector3d& vertex : mesh.vertices) {
    vertex.z() = 0.4 * std::sin(0.9 * vertex.x()) * std::cos(1.3 * vertex.y()) +
                 0.1 * std::sin(5.0 * vertex.x() + 2.0 * vertex.y());
  }
  return mesh;
}

class ConstantTexture : public Texture {
 public:
  explicit ConstantTexture(const Eigen::Vector3f& albedo) : albedo_(albedo) {}
  Eigen::Vector3f Albedo(const Eigen::Vector3d&,
                         const Eigen::Vector3d&) const override {
    return albedo_;
  }

 private:
  Eigen::Vector3f albedo_;
};

// A 3D checkerboard of 10 cm cells.
class CheckerTexture : public Texture {
 public:
  Eigen::Vector3f Albedo(const Eigen::Vector3d& point,
                         const Eigen::Vector3d&) const override {
    const Eigen::Vector3d cell = (point / 0.1).array().floor();
    const bool odd = static_cast<int64_t>(cell.sum()) % 2 != 0;
    return odd ? Eigen::Vector3f(0.8f, 0.7f, 0.5f)
               : Eigen::Vector3f(0.2f, 0.25f, 0.3f);
  }
};

Camera MakeCamera(CameraModelId model_id, int width, int height,
                  std::vector<double> params) {
  Camera camera;
  camera.camera_id = 1;
  camera.model_id = model_id;
  camera.width = width;
  camera.height = height;
  camera.params = std::move(params);
  return camera;
}

Camera Pinhole(int width, int height, double focal) {
  return MakeCamera(CameraModelId::kPinhole, width, height,
                    {focal, focal, width / 2.0, height / 2.0});
}

// The pose of a camera at `centre` looking at `target`, with the image's
// "up" (-y) toward `up` as far as possible.
Rigid3d LookAt(const Eigen::Vector3d& centre, const Eigen::Vector3d& target,
               const Eigen::Vector3d& up) {
  const Eigen::Vector3d z = (target - centre).normalized();
  const Eigen::Vector3d y = -(up - up.dot(z) * z).normalized();
  const Eigen::Vector3d x = y.cross(z);
  Eigen::Matrix3d cam_from_world_rotation;
  cam_from_world_rotation << x.transpose(), y.transpose(), z.transpose();
  Rigid3d cam_from_world;
  cam_from_world.rotation = Eigen::Quaterniond(cam_from_world_rotation);
  cam_from_world.translation = -(cam_from_world_rotation * centre);
  return cam_from_world;
}

// Options with every effect that blurs a measurement turned off, and levels
// proportional to radiance.
RenderOptions CleanOptions() {
  RenderOptions options;
  options.water.backscatter_strength = 0.0;
  options.light.position_in_cam.setZero();
  options.light.cone_half_angle_deg = 80.0;
  options.light.cone_falloff_deg = 0.0;
  options.light.vignetting = 0.0;
  options.sensor.noise_sigma = 0.0;
  options.sensor.supersampling = 1;
  options.sensor.srgb = false;
  return options;
}

// Entry distance of the ray into the box within [0, max_distance], if any.
std::optional<double> BoxEntry(const Eigen::Vector3d& lower,
                               const Eigen::Vector3d& upper,
                               const Eigen::Vector3d& origin,
                               const Eigen::Vector3d& direction,
                               double max_distance) {
  double entry = 0.0;
  double exit = max_distance;
  for (int axis = 0; axis < 3; ++axis) {
    double near = (lower(axis) - origin(axis)) / direction(axis);
    double far = (upper(axis) - origin(axis)) / direction(axis);
    if (near > far) std::swap(near, far);
    entry = std::max(entry, near);
    exit = std::min(exit, far);
  }
  if (entry > exit) return std::nullopt;
  return entry;
}

cv::Vec3b Bgr(const cv::Mat& image, int row, int col) {
  return image.at<cv::Vec3b>(row, col);
}

bool SameBytes(const cv::Mat& a, const cv::Mat& b) {
  if (a.size() != b.size() || a.type() != b.type()) return false;
  const size_t bytes = a.total() * a.elemSize();
  return std::memcmp(a.data, b.data, bytes) == 0;
}

TEST(PixelRayInWorld, FollowsTheColmapPixelConvention) {
  const Camera camera = Pinhole(640, 480, 500);
  const Rigid3d cam_from_world =
      LookAt({1, 2, 3}, {1, 2, 0}, Eigen::Vector3d::UnitY());
  // (320, 240) is the principal point: the corner shared by the four centre
  // pixels, on the optical axis.
  const Ray axis = PixelRayInWorld(camera, cam_from_world, {320, 240});
  EXPECT_LT((axis.origin - Eigen::Vector3d(1, 2, 3)).norm(), 1e-15);
  EXPECT_LT((axis.direction + Eigen::Vector3d::UnitZ()).norm(), 1e-15);
  // The centre of pixel (0, 0) is (0.5, 0.5), half a pixel in from the
  // corner in both directions; image up is world +y.
  const Ray corner = PixelRayInWorld(camera, cam_from_world, {0.5, 0.5});
  const Eigen::Vector3d expected =
      Eigen::Vector3d(-319.5 / 500, 239.5 / 500, -1).normalized();
  EXPECT_LT((corner.direction - expected).norm(), 1e-15);
}

// Acceptance 1 (first half): a pixel's ray-cast hit reprojects to the same
// pixel through our camera models.
TEST(PixelRayInWorld, HitsReprojectToTheirPixel) {
  const RayCaster caster(BumpyFloor(200));
  const std::vector<Camera> cameras = {
      Pinhole(1024, 768, 880),
      MakeCamera(CameraModelId::kOpenCV, 1024, 768,
                 {880, 885, 515.3, 380.2, -0.28, 0.09, 1e-3, -5e-4}),
      MakeCamera(CameraModelId::kOpenCVFisheye, 1024, 768,
                 {460, 462, 511.2, 385.7, 0.05, -0.01, 0.002, -5e-4}),
  };
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (const Camera& camera : cameras) {
    double max_error = 0.0;
    int hits = 0;
    int rays = 0;
    for (int pose = 0; pose < 5; ++pose) {
      const Eigen::Vector3d centre(8 * uniform(rng) - 4, 8 * uniform(rng) - 4,
                                   2 + 3 * uniform(rng));
      const Eigen::Vector3d target =
          centre +
          Eigen::Vector3d(2 * uniform(rng) - 1, 2 * uniform(rng) - 1, -3);
      const Eigen::Vector3d up(std::cos(6.3 * uniform(rng)),
                               std::sin(6.3 * uniform(rng)), 0);
      const Rigid3d cam_from_world = LookAt(centre, target, up);
      for (int k = 0; k < 2000; ++k, ++rays) {
        const Eigen::Vector2d pixel(camera.width * uniform(rng),
                                    camera.height * uniform(rng));
        const Ray ray = PixelRayInWorld(camera, cam_from_world, pixel);
        const std::optional<RayCaster::Hit> hit =
            caster.Intersect(ray.origin, ray.direction);
        if (!hit) continue;
        ++hits;
        const Eigen::Vector2d reprojected =
            camera.ImgFromCam(cam_from_world * hit->point_in_world);
        max_error = std::max(max_error, (reprojected - pixel).norm());
      }
    }
    EXPECT_GT(hits, rays / 2) << camera.ModelName();
    EXPECT_LT(max_error, 1e-6) << camera.ModelName();
    std::printf(
        "[ figures ] %s 1024x768: %d ray-cast hits, max reprojection "
        "error %.2e px\n",
        camera.ModelName().c_str(), hits, max_error);
  }
}

TEST(Renderer, DepthIsTheAnalyticRangeOfThePixelCentreRay) {
  // A plane through (0, 0, -1) tilted 30 degrees about x, facing up, seen
  // obliquely so that the top of the image looks past its far edge.
  const double tilt = 30.0 * M_PI / 180.0;
  const Eigen::Vector3d u(6, 0, 0);
  const Eigen::Vector3d v(0, 6 * std::cos(tilt), 6 * std::sin(tilt));
  const Eigen::Vector3d corner = Eigen::Vector3d(0, 0, -1) - 0.5 * u - 0.5 * v;
  TriangleMesh mesh;
  AddGrid(corner, u, v, 7, 5, &mesh);
  const Eigen::Vector3d normal = u.cross(v).normalized();
  const RayCaster caster(mesh);
  const ConstantTexture texture({0.5f, 0.5f, 0.5f});
  const Rigid3d cam_from_world =
      LookAt({0.2, -3.0, 1.0}, {0, 1.5, -0.5}, Eigen::Vector3d::UnitZ());
  for (const Camera& camera :
       {Pinhole(160, 120, 110),
        MakeCamera(CameraModelId::kOpenCV, 160, 120,
                   {110, 111, 80.5, 59.5, -0.2, 0.05, 1e-3, -1e-3})}) {
    for (const int supersampling : {1, 2, 3}) {
      RenderOptions options;
      options.sensor.supersampling = supersampling;
      const RenderedImage rendered =
          RenderImage(caster, texture, camera, cam_from_world, options, 1, 0);
      ASSERT_EQ(rendered.depth_m.type(), CV_64F);
      int misses = 0;
      double max_relative_error = 0.0;
      for (int row = 0; row < 120; ++row) {
        for (int col = 0; col < 160; ++col) {
          const Ray ray =
              PixelRayInWorld(camera, cam_from_world, {col + 0.5, row + 0.5});
          const double depth = rendered.depth_m.at<double>(row, col);
          const std::optional<RayCaster::Hit> hit = caster.Intersect(ray);
          ASSERT_EQ(std::isnan(depth), !hit.has_value());
          if (!hit) {
            ++misses;
            continue;
          }
          EXPECT_EQ(depth, hit->distance);
          const double expected =
              normal.dot(corner - ray.origin) / normal.dot(ray.direction);
          max_relative_error = std::max(max_relative_error,
                                        std::abs(depth - expected) / expected);
        }
      }
      EXPECT_GT(misses, 100);
      EXPECT_LT(misses, 160 * 120 / 2);
      EXPECT_LT(max_relative_error, 1e-12);
    }
  }
}

TEST(Renderer, SamplesSpreadEvenlyOverEachPixel) {
  // A half-plane whose edge falls 0.4 px into column 80: the samples right
  // of it (x > 80.4) see a lit wall, the others black water. The edge
  // pixel's level relative to a fully covered neighbour is then the share of
  // its samples right of 0.4: 1 at supersampling 1 (the centre), 1/2 at 2
  // (0.25, 0.75), 2/3 at 3 (1/6, 1/2, 5/6), 1/2 at 4.
  const Camera camera = Pinhole(160, 20, 1000);
  const double edge_x = 0.4 * 2.0 / 1000.0;  // at 2 m
  TriangleMesh mesh;
  AddGrid({edge_x, -1, 2}, {0, 2, 0}, {1, 0, 0}, 1, 1, &mesh);
  const RayCaster caster(mesh);
  const ConstantTexture texture({0.8f, 0.8f, 0.8f});
  RenderOptions options = CleanOptions();
  options.water.attenuation_per_m.setZero();
  options.light.intensity = 4.0;
  for (const auto& [supersampling, share] :
       {std::make_pair(1, 1.0), std::make_pair(2, 0.5),
        std::make_pair(3, 2.0 / 3.0), std::make_pair(4, 0.5)}) {
    options.sensor.supersampling = supersampling;
    const cv::Mat image =
        RenderImage(caster, texture, camera, Rigid3d(), options, 1, 0).image;
    EXPECT_EQ(Bgr(image, 10, 79)[1], 0) << supersampling;
    const double covered = Bgr(image, 10, 81)[1];
    ASSERT_GT(covered, 150) << supersampling;
    EXPECT_NEAR(Bgr(image, 10, 80)[1] / covered, share, 0.01) << supersampling;
  }
}

// Mean 8-bit level per channel (R, G, B) over a window, and the model's
// prediction there for a camera at the origin looking along +z at the plane
// z = distance, with the lamp at the camera.
struct PatchLevels {
  Eigen::Vector3d measured = Eigen::Vector3d::Zero();
  Eigen::Vector3d predicted = Eigen::Vector3d::Zero();
};

PatchLevels MeasurePlane(double distance, double gain,
                         const Eigen::Vector3f& albedo) {
  const Camera camera = Pinhole(160, 120, 150);
  RenderOptions options = CleanOptions();
  options.water.attenuation_per_m = {0.3, 0.1, 0.05};
  options.light.intensity = 5.5;
  options.sensor.gain = gain;
  const RayCaster caster(FacingPlane(distance));
  const ConstantTexture texture(albedo);
  const RenderedImage rendered =
      RenderImage(caster, texture, camera, Rigid3d(), options, 1, 0);
  PatchLevels levels;
  int count = 0;
  for (int row = 50; row < 70; ++row) {
    for (int col = 70; col < 90; ++col, ++count) {
      const cv::Vec3b bgr = Bgr(rendered.image, row, col);
      levels.measured += Eigen::Vector3d(bgr[2], bgr[1], bgr[0]);
      const Ray ray =
          PixelRayInWorld(camera, Rigid3d(), {col + 0.5, row + 0.5});
      const double range = distance / ray.direction.z();
      // n.l = direction.z; light and camera paths are both `range` long.
      const Eigen::Vector3d radiance = albedo.cast<double>() *
                                       options.light.intensity *
                                       ray.direction.z() / (range * range);
      levels.predicted +=
          255.0 * gain *
          radiance.cwiseProduct((-2.0 * range * options.water.attenuation_per_m)
                                    .array()
                                    .exp()
                                    .matrix());
    }
  }
  levels.measured /= count;
  levels.predicted /= count;
  return levels;
}

TEST(Renderer, BrightnessFallsWithRangeAsModelled) {
  const Eigen::Vector3f albedo(1.0f, 0.6f, 0.3f);
  const double gain_near = 1.0;
  const double gain_far = 8.0;  // keeps 4 m in the upper half of 8 bits
  const PatchLevels near = MeasurePlane(2.0, gain_near, albedo);
  const PatchLevels far = MeasurePlane(4.0, gain_far, albedo);
  for (int c = 0; c < 3; ++c) {
    ASSERT_GT(near.measured(c), 60) << c;
    ASSERT_LT(near.measured(c), 250) << c;
    ASSERT_GT(far.measured(c), 60) << c;
    ASSERT_LT(far.measured(c), 250) << c;
    EXPECT_NEAR(near.measured(c) / near.predicted(c), 1.0, 0.01) << c;
    EXPECT_NEAR(far.measured(c) / far.predicted(c), 1.0, 0.01) << c;
  }
  const Eigen::Vector3d measured_ratio =
      (far.measured / gain_far).cwiseQuotient(near.measured / gain_near);
  const Eigen::Vector3d predicted_ratio =
      (far.predicted / gain_far).cwiseQuotient(near.predicted / gain_near);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(measured_ratio(c) / predicted_ratio(c), 1.0, 0.02) << c;
  }
  // Red is absorbed fastest: c = 0.3 / m against 0.05 / m for blue over 4 m
  // more of water.
  EXPECT_LT(measured_ratio(0), 0.4 * measured_ratio(2));
  EXPECT_NEAR(measured_ratio(0) / measured_ratio(2), std::exp(-4.0 * 0.25),
              0.02);
  std::printf(
      "[ figures ] 4 m / 2 m brightness (R, G, B): measured %.4f "
      "%.4f %.4f, model %.4f %.4f %.4f\n",
      measured_ratio(0), measured_ratio(1), measured_ratio(2),
      predicted_ratio(0), predicted_ratio(1), predicted_ratio(2));
}

// The visible range against the renderer itself, default water, lamp and
// sensor (noise switched off to measure, its sigma kept for the range): a
// grey card (18 %) on the optical axis lifts the image above a black one at
// the same range by more than 3 noise sigmas at 0.9 of the range, by less
// at 1.1. Clearer water or a brighter lamp see farther.
TEST(Renderer, VisibleRangeIsWhereAGreyCardFadesIntoTheVeil) {
  const RenderOptions defaults;
  const double range = VisibleRange(defaults);
  std::printf("[ figures ] visible range, default water: %.3f m\n", range);
  EXPECT_GT(range, 4.0);
  EXPECT_LT(range, 10.0);
  const Camera camera = Pinhole(40, 30, 400);  // 6 degrees across
  RenderOptions options = defaults;
  options.sensor.noise_sigma = 0.0;
  options.sensor.supersampling = 1;
  const auto centre_levels = [&](double distance, float albedo) {
    const RayCaster caster(FacingPlane(distance));
    const ConstantTexture texture({albedo, albedo, albedo});
    const RenderedImage rendered =
        RenderImage(caster, texture, camera, Rigid3d(), options, 1, 0);
    const cv::Vec3b bgr = Bgr(rendered.image, 15, 20);
    return Eigen::Vector3d(bgr[2], bgr[1], bgr[0]);
  };
  const double threshold = 3.0 * defaults.sensor.noise_sigma;
  for (const double factor : {0.9, 1.1}) {
    const Eigen::Vector3d contrast = centre_levels(factor * range, 0.18f) -
                                     centre_levels(factor * range, 0.0f);
    std::printf("[ figures ] at %.2f m: %.0f %.0f %.0f levels above the veil\n",
                factor * range, contrast(0), contrast(1), contrast(2));
    if (factor < 1.0) {
      EXPECT_GT(contrast.maxCoeff(), threshold);
    } else {
      EXPECT_LT(contrast.maxCoeff(), threshold);
    }
  }
  RenderOptions clearer = defaults;
  clearer.water.attenuation_per_m *= 0.5;
  EXPECT_GT(VisibleRange(clearer), 1.3 * range);
  RenderOptions brighter = defaults;
  brighter.light.intensity *= 4.0;
  EXPECT_GT(VisibleRange(brighter), range);
  EXPECT_THROW(VisibleRange(defaults, 0.0), Error);
}

TEST(Renderer, OutsideTheLightConeOnlyTheVeilRemains) {
  const Camera camera = Pinhole(160, 120, 60);  // 106 degrees across
  RenderOptions options = CleanOptions();
  options.water.backscatter_strength = 0.3;
  options.light.cone_half_angle_deg = 10.0;
  options.light.cone_falloff_deg = 2.0;
  options.light.intensity = 5.0;
  const RayCaster caster(FacingPlane(2.0));
  const ConstantTexture texture({0.5f, 0.5f, 0.5f});
  const RenderedImage rendered =
      RenderImage(caster, texture, camera, Rigid3d(), options, 1, 0);
  const Eigen::Vector3d veil =
      options.water.backscatter_strength * options.water.backscatter_rgb;
  int outside = 0;
  int inside = 0;
  for (int row = 0; row < 120; ++row) {
    for (int col = 0; col < 160; ++col) {
      const Ray ray =
          PixelRayInWorld(camera, Rigid3d(), {col + 0.5, row + 0.5});
      const double angle_deg = std::acos(ray.direction.z()) * 180.0 / M_PI;
      const double range = 2.0 / ray.direction.z();
      const Eigen::Vector3d veil_levels =
          255.0 * veil.cwiseProduct(
                      (Eigen::Vector3d::Ones().array() -
                       (-range * options.water.attenuation_per_m).array().exp())
                          .matrix());
      const cv::Vec3b bgr = Bgr(rendered.image, row, col);
      const Eigen::Vector3d levels(bgr[2], bgr[1], bgr[0]);
      if (angle_deg > 11.5) {
        ++outside;
        EXPECT_LE((levels - veil_levels).cwiseAbs().maxCoeff(), 0.5 + 1e-9)
            << row << " " << col;
      } else if (angle_deg < 8.5) {
        ++inside;
        EXPECT_GT(levels(1), veil_levels(1) + 50) << row << " " << col;
      }
    }
  }
  EXPECT_GT(outside, 10000);
  EXPECT_GT(inside, 100);
}

TEST(Renderer, CastsShadows) {
  // A box floating between the camera and a wall 3 m away, lit from 0.8 m to
  // the camera's right, so that its shadow falls visibly to its left.
  const Eigen::Vector3d lower(-0.2, -0.2, 1.3);
  const Eigen::Vector3d upper(0.2, 0.2, 1.7);
  TriangleMesh mesh = FacingPlane(3.0);
  AddBox(lower, upper, &mesh);
  const RayCaster caster(mesh);
  const ConstantTexture texture({0.6f, 0.6f, 0.6f});
  const Camera camera = Pinhole(160, 120, 120);
  RenderOptions options = CleanOptions();
  options.water.backscatter_strength = 0.2;
  options.light.position_in_cam = {0.8, 0.0, 0.0};
  options.light.intensity = 8.0;
  const RenderedImage rendered =
      RenderImage(caster, texture, camera, Rigid3d(), options, 1, 0);
  const Eigen::Vector3d light = options.light.position_in_cam;
  int shadowed = 0;
  int lit = 0;
  int wrong = 0;
  for (int row = 0; row < 120; ++row) {
    for (int col = 0; col < 160; ++col) {
      const Ray ray =
          PixelRayInWorld(camera, Rigid3d(), {col + 0.5, row + 0.5});
      if (BoxEntry(lower, upper, ray.origin, ray.direction, 1e9)) continue;
      const Eigen::Vector3d point = ray.direction * (3.0 / ray.direction.z());
      const Eigen::Vector3d to_light = light - point;
      const bool in_shadow =
          BoxEntry(lower, upper, point, to_light.normalized(), to_light.norm())
              .has_value();
      const double veil_green =
          255.0 * options.water.backscatter_strength *
          options.water.backscatter_rgb.y() *
          (1.0 - std::exp(-point.norm() * options.water.attenuation_per_m.y()));
      const int green = Bgr(rendered.image, row, col)[1];
      if (in_shadow) {
        ++shadowed;
        wrong += std::abs(green - veil_green) > 0.5 + 1e-9;
      } else {
        ++lit;
        wrong += green < veil_green + 5;
      }
    }
  }
  EXPECT_GT(shadowed, 300);
  EXPECT_GT(lit, 5000);
  EXPECT_LE(wrong, 2);
}

// A survey-like view: bumpy textured floor seen obliquely through a lens with
// distortion, with every sensor effect on.
struct SurveyScene {
  SurveyScene() : caster(BumpyFloor(100)) {
    options.sensor.noise_sigma = 3.0;
    options.sensor.jpeg_quality = 90;
    options.sensor.marine_snow_per_m3 = 30.0;
    options.sensor.marine_snow_range_m = 3.0;
    options.sensor.supersampling = 2;
  }
  RayCaster caster;
  CheckerTexture texture;
  Camera camera = MakeCamera(CameraModelId::kOpenCV, 200, 150,
                             {170, 171, 100.3, 74.8, -0.2, 0.05, 1e-3, -1e-3});
  Rigid3d cam_from_world =
      LookAt({0.3, -1.0, 2.5}, {0.0, 1.0, 0.0}, Eigen::Vector3d::UnitY());
  RenderOptions options;
};

TEST(Renderer, SameBytesForAnyThreadCount) {
  std::vector<RenderedImage> images;
  for (const int threads : {1, 2, 4}) {
    const tbb::global_control parallelism(
        tbb::global_control::max_allowed_parallelism, threads);
    // The arena's concurrency also sets how TBB splits the rows into tasks.
    tbb::task_arena arena(threads);
    arena.execute([&] {
      const SurveyScene scene;  // the BVH is built under this count too
      images.push_back(RenderImage(scene.caster, scene.texture, scene.camera,
                                   scene.cam_from_world, scene.options, 42, 7));
    });
  }
  ASSERT_FALSE(images[0].jpeg.empty());
  for (size_t k = 1; k < images.size(); ++k) {
    EXPECT_TRUE(SameBytes(images[0].image, images[k].image)) << k;
    EXPECT_TRUE(SameBytes(images[0].depth_m, images[k].depth_m)) << k;
    EXPECT_EQ(images[0].jpeg, images[k].jpeg) << k;
  }
  const SurveyScene scene;
  const Renderer renderer(scene.caster, scene.texture, scene.camera,
                          scene.options);
  EXPECT_TRUE(SameBytes(renderer.Render(scene.cam_from_world, 42, 7).image,
                        images[0].image));
  EXPECT_FALSE(SameBytes(renderer.Render(scene.cam_from_world, 43, 7).image,
                         images[0].image));
  EXPECT_FALSE(SameBytes(renderer.Render(scene.cam_from_world, 42, 8).image,
                         images[0].image));
  // The JPEG bytes decode to the image.
  EXPECT_TRUE(SameBytes(cv::imdecode(images[0].jpeg, cv::IMREAD_UNCHANGED),
                        images[0].image));
}

TEST(Renderer, NoiseIsGaussianWithTheConfiguredSigma) {
  const Camera camera = Pinhole(200, 150, 150);
  RenderOptions options = CleanOptions();
  options.light.intensity = 2.0;
  const RayCaster caster(FacingPlane(2.0));
  const ConstantTexture texture({0.5f, 0.5f, 0.5f});
  const Renderer clean(caster, texture, camera, options);
  options.sensor.noise_sigma = 3.0;
  const Renderer noisy(caster, texture, camera, options);
  cv::Mat difference;
  cv::Mat clean_image = clean.Render(Rigid3d(), 5, 0).image;
  noisy.Render(Rigid3d(), 5, 0).image.convertTo(difference, CV_64F);
  clean_image.convertTo(clean_image, CV_64F);
  difference -= clean_image;
  cv::Scalar mean;
  cv::Scalar stddev;
  cv::meanStdDev(difference.reshape(1), mean, stddev);
  EXPECT_NEAR(mean[0], 0.0, 0.05);
  // sqrt(3^2 + 1/12): the noise plus its own quantisation.
  EXPECT_NEAR(stddev[0], std::sqrt(9.0 + 1.0 / 12.0), 0.05);
}

TEST(Renderer, MarineSnowStaysInTheWaterInFrontOfSurfaces) {
  const Camera camera = Pinhole(200, 150, 150);
  RenderOptions options = CleanOptions();
  options.light.position_in_cam = {0, -0.3, 0};
  options.light.intensity = 2.0;
  options.sensor.marine_snow_range_m = 3.0;
  const ConstantTexture texture({0.3f, 0.3f, 0.3f});
  RenderOptions snowy = options;
  snowy.sensor.marine_snow_per_m3 = 50.0;
  // A wall nearer than any particle hides them all.
  {
    const RayCaster caster(FacingPlane(0.15));
    EXPECT_TRUE(SameBytes(
        RenderImage(caster, texture, camera, Rigid3d(), options, 3, 0).image,
        RenderImage(caster, texture, camera, Rigid3d(), snowy, 3, 0).image));
  }
  // A wall at 5 m leaves them in view, brighter than the wall.
  const RayCaster caster(FacingPlane(5.0));
  const cv::Mat clear =
      RenderImage(caster, texture, camera, Rigid3d(), options, 3, 0).image;
  const cv::Mat with_snow =
      RenderImage(caster, texture, camera, Rigid3d(), snowy, 3, 0).image;
  cv::Mat brighter;
  cv::subtract(with_snow, clear, brighter);
  cv::Mat darker;
  cv::subtract(clear, with_snow, darker);
  const int changed = cv::countNonZero(brighter.reshape(1));
  EXPECT_GT(changed, 50);
  EXPECT_LT(changed, 200 * 150 * 3 / 4);
  EXPECT_EQ(cv::countNonZero(darker.reshape(1)), 0);
}

TEST(Renderer, MonochromeSensorRecordsLuminance) {
  const Camera camera = Pinhole(80, 60, 60);
  RenderOptions options = CleanOptions();
  const RayCaster caster(FacingPlane(2.0));
  const ConstantTexture texture({0.9f, 0.3f, 0.1f});
  const cv::Mat colour =
      RenderImage(caster, texture, camera, Rigid3d(), options, 1, 0).image;
  options.sensor.rgb = false;
  const cv::Mat grey =
      RenderImage(caster, texture, camera, Rigid3d(), options, 1, 0).image;
  ASSERT_EQ(grey.type(), CV_8UC1);
  ASSERT_EQ(colour.type(), CV_8UC3);
  for (int row = 0; row < 60; row += 7) {
    for (int col = 0; col < 80; col += 7) {
      const cv::Vec3b bgr = Bgr(colour, row, col);
      const double luminance =
          0.2126 * bgr[2] + 0.7152 * bgr[1] + 0.0722 * bgr[0];
      EXPECT_NEAR(grey.at<uint8_t>(row, col), luminance, 1.0);
    }
  }
}

TEST(Renderer, SrgbEncodesLikeACamera) {
  const Camera camera = Pinhole(80, 60, 60);
  RenderOptions options = CleanOptions();
  options.light.intensity = 1.0;
  const RayCaster caster(FacingPlane(2.0));
  const ConstantTexture texture({0.9f, 0.3f, 0.03f});
  const cv::Mat linear =
      RenderImage(caster, texture, camera, Rigid3d(), options, 1, 0).image;
  options.sensor.srgb = true;
  const cv::Mat encoded =
      RenderImage(caster, texture, camera, Rigid3d(), options, 1, 0).image;
  const auto srgb = [](double level) {
    const double x = std::clamp(level / 255.0, 0.0, 1.0);
    return 255.0 * (x <= 0.0031308 ? 12.92 * x
                                   : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055);
  };
  for (int row = 0; row < 60; row += 5) {
    for (int col = 0; col < 80; col += 5) {
      for (int c = 0; c < 3; ++c) {
        // The linear level is itself rounded: its value lies within +-0.5.
        const double level = linear.at<cv::Vec3b>(row, col)[c];
        const double value = encoded.at<cv::Vec3b>(row, col)[c];
        EXPECT_GE(value, std::floor(srgb(level - 0.5) + 0.5) - 0.01);
        EXPECT_LE(value, std::floor(srgb(level + 0.5) + 0.5) + 0.01);
        if (level > 2) {
          EXPECT_GT(value, level);  // the curve lifts the darks
        }
      }
    }
  }
}

TEST(RenderOptions, JsonRoundTripsAndRejectsTypos) {
  RenderOptions options;
  options.water.attenuation_per_m = {0.5, 0.2, 0.1};
  options.light.cone_half_angle_deg = 33.0;
  options.sensor.supersampling = 3;
  options.sensor.rgb = false;
  const nlohmann::json json = options;
  const RenderOptions read = json.get<RenderOptions>();
  EXPECT_EQ(nlohmann::json(read), json);
  EXPECT_EQ(read.water.attenuation_per_m, options.water.attenuation_per_m);
  EXPECT_EQ(read.sensor.supersampling, 3);

  // Absent keys keep their defaults.
  const RenderOptions partial =
      nlohmann::json::parse(R"({"sensor": {"gain": 2.5}})")
          .get<RenderOptions>();
  EXPECT_EQ(partial.sensor.gain, 2.5);
  EXPECT_EQ(nlohmann::json(partial.water), nlohmann::json(WaterOptions()));
  // Also within a section, and on top of values that are not defaults.
  RenderOptions tuned;
  tuned.sensor.gain = 3.0;
  from_json(nlohmann::json::parse(R"({"sensor": {"noise_sigma": 1.5}})"),
            tuned);
  EXPECT_EQ(tuned.sensor.gain, 3.0);
  EXPECT_EQ(tuned.sensor.noise_sigma, 1.5);

  for (const char* bad : {R"({"sensor": {"gian": 2}})", R"({"watr": {}})",
                          R"({"water": {"attenuation_per_m": [1, 2]}})",
                          R"({"sensor": {"supersampling": "two"}})"}) {
    EXPECT_THROW(nlohmann::json::parse(bad).get<RenderOptions>(), Error) << bad;
  }
}

TEST(RenderOptions, CheckRejectsNonsense) {
  EXPECT_NO_THROW(RenderOptions().Check());
  RenderOptions options;
  options.water.attenuation_per_m.x() = -0.1;
  EXPECT_THROW(options.Check(), Error);
  options = RenderOptions();
  options.sensor.supersampling = 0;
  EXPECT_THROW(options.Check(), Error);
  options = RenderOptions();
  options.sensor.jpeg_quality = 101;
  EXPECT_THROW(options.Check(), Error);
  options = RenderOptions();
  options.light.direction_in_cam.setZero();
  EXPECT_THROW(options.Check(), Error);
  options = RenderOptions();
  options.water.backscatter_rgb.z() = 1.5;
  EXPECT_THROW(options.Check(), Error);
  const RayCaster caster(FacingPlane(2.0));
  const ConstantTexture texture({0.5f, 0.5f, 0.5f});
  Camera camera = Pinhole(80, 60, 60);
  camera.params.pop_back();
  EXPECT_THROW(Renderer(caster, texture, camera, RenderOptions()), Error);
}

// Options for measuring laser spots alone: no lamp, no water, no noise,
// linear levels.
RenderOptions LaserOnlyOptions(int supersampling) {
  RenderOptions options = CleanOptions();
  options.light.intensity = 0.0;
  options.water.attenuation_per_m.setZero();
  options.sensor.supersampling = supersampling;
  return options;
}

// Intensity-weighted centroid (COLMAP pixel convention) of one channel
// within `radius` pixels of `around`.
Eigen::Vector2d Centroid(const cv::Mat& image, int channel,
                         const Eigen::Vector2d& around, double radius,
                         double* total) {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  *total = 0.0;
  for (int row = std::max(0, static_cast<int>(around.y() - radius));
       row <= std::min(image.rows - 1, static_cast<int>(around.y() + radius));
       ++row) {
    for (int col = std::max(0, static_cast<int>(around.x() - radius));
         col <= std::min(image.cols - 1, static_cast<int>(around.x() + radius));
         ++col) {
      const Eigen::Vector2d centre(col + 0.5, row + 0.5);
      if ((centre - around).norm() > radius) continue;
      const double value = image.at<cv::Vec3b>(row, col)[channel];
      sum += value * centre;
      *total += value;
    }
  }
  return sum / *total;
}

// A 20 m square plane through `centre` with unit normal `normal` (towards
// the camera).
TriangleMesh Plane(const Eigen::Vector3d& centre,
                   const Eigen::Vector3d& normal) {
  const Eigen::Vector3d u = normal.cross(Eigen::Vector3d::UnitX()).normalized();
  const Eigen::Vector3d v = normal.cross(u);
  TriangleMesh mesh;
  AddGrid(centre - 10.0 * u - 10.0 * v, 20.0 * v, 20.0 * u, 4, 4, &mesh);
  return mesh;
}

// Acceptance (issue 3): in a noise-free, unattenuated laser image the
// spot's intensity centroid is the projection of the true laser-surface
// hit, through a distorted camera, on planes tilted up to 45 degrees.
TEST(RendererLasers, SpotCentroidIsTheProjectedTrueHit) {
  const Camera camera = MakeCamera(CameraModelId::kSimpleRadial, 640, 480,
                                   {600.0, 321.0, 239.0, -0.04});
  const ConstantTexture texture(Eigen::Vector3f(0.5f, 0.5f, 0.5f));
  FrameOptions frame;
  frame.optics.peak_level = 2.5;  // below saturation on these planes
  double worst_px = 0.0;
  int spots = 0;
  for (const double tilt_deg : {0.0, 25.0, 45.0}) {
    const double tilt = tilt_deg * M_PI / 180.0;
    const Eigen::Vector3d normal(std::sin(tilt) * 0.6, std::sin(tilt) * 0.8,
                                 -std::cos(tilt));
    const RayCaster caster(Plane({0.1, -0.05, 2.5}, normal));
    const Renderer renderer(caster, texture, camera, LaserOnlyOptions(3));
    for (const char* setup : {"A", "B", "C"}) {
      LaserOptions lasers;
      lasers.setup = setup;
      frame.lasers = TrueLaserSetup(lasers).lasers;
      const Rigid3d cam_from_world;
      const RenderedImage rendered =
          renderer.Render(cam_from_world, 1, 0, frame);
      for (const Laser& laser : frame.lasers) {
        const LaserSpotTruth truth =
            TrueLaserSpot(caster, camera, cam_from_world, laser);
        ASSERT_TRUE(truth.visible) << setup << " " << laser.name;
        double total = 0.0;
        const Eigen::Vector2d centroid =
            Centroid(rendered.image, 2, truth.pixel, 14.0, &total);
        EXPECT_GT(total, 300.0);  // a spot, not a stray pixel
        const double error = (centroid - truth.pixel).norm();
        EXPECT_LT(error, 0.05)
            << "setup " << setup << " " << laser.name << " tilt " << tilt_deg;
        worst_px = std::max(worst_px, error);
        ++spots;
      }
    }
  }
  std::printf(
      "[ figures ] laser spot centroid vs projected true hit: worst "
      "%.4f px over %d spots (tilts 0/25/45 deg, set-ups A/B/C)\n",
      worst_px, spots);
}

// The spot lies where the beam first meets a surface, is seen only where
// the camera sees that surface, and fades with range as the water
// attenuates the beam there and back.
TEST(RendererLasers, FootprintIsTheFirstHitSeenByTheCameraAndAttenuated) {
  const Camera camera = Pinhole(320, 240, 300);
  const ConstantTexture texture(Eigen::Vector3f(0.5f, 0.5f, 0.5f));
  FrameOptions frame;
  Laser laser;
  laser.name = "L";
  laser.origin_in_cam = {0.2, 0.0, 0.0};
  laser.colour = {1.0, 0.0, 0.0};
  frame.lasers = {laser};
  // Narrow and bright enough that 8-bit rounding loses little of a spot.
  frame.optics.waist_radius_m = 0.004;
  frame.optics.divergence_mrad = 1.0;
  frame.optics.peak_level = 6.0;
  const RenderOptions options = LaserOnlyOptions(2);

  // A wall at 3 m and a 10 cm plate at 1 m whose near edge is at x =
  // plate_x; the laser image and the truth of its spot.
  const auto with_plate = [&](double plate_x, LaserSpotTruth* truth) {
    TriangleMesh mesh = FacingPlane(3.0);
    AddGrid({plate_x, -0.05, 1.0}, {0, 0.1, 0}, {0.1, 0, 0}, 1, 1, &mesh);
    const RayCaster caster(mesh);
    *truth = TrueLaserSpot(caster, camera, Rigid3d(), laser);
    return Renderer(caster, texture, camera, options)
        .Render(Rigid3d(), 1, 0, frame)
        .image;
  };
  // The plate covers the spot (at (0.2, 0, 3)) but leaves the beam free.
  LaserSpotTruth hidden;
  const cv::Mat hidden_image = with_plate(0.05, &hidden);
  EXPECT_FALSE(hidden.visible);
  EXPECT_EQ(cv::countNonZero(hidden_image.reshape(1)), 0);
  // The plate lies across the beam: the spot is on the plate.
  LaserSpotTruth blocked;
  const cv::Mat blocked_image = with_plate(0.15, &blocked);
  ASSERT_TRUE(blocked.visible);
  EXPECT_NEAR(blocked.range_m, 1.0, 1e-12);
  double total = 0.0;
  const Eigen::Vector2d centroid =
      Centroid(blocked_image, 2, blocked.pixel, 8.0, &total);
  EXPECT_LT((centroid - blocked.pixel).norm(), 0.1);
  EXPECT_EQ(cv::countNonZero(blocked_image.reshape(1)),
            cv::countNonZero(
                blocked_image(cv::Rect(static_cast<int>(blocked.pixel.x()) - 8,
                                       static_cast<int>(blocked.pixel.y()) - 8,
                                       17, 17))
                    .clone()
                    .reshape(1)));
  // Attenuation: the spot's red sum at 2 m and 3 m (the beam spreads but
  // keeps its power; the footprint is larger but no dimmer in total)
  // differs by exp(-c (2 + 2)) / exp(-c (3 + 3)) and by the 1/d^2 of the
  // camera's view of the spot, the Lambertian radiance being the same.
  RenderOptions water = options;
  water.water.attenuation_per_m = {0.3, 0.0, 0.0};
  double sums[2];
  for (const int i : {0, 1}) {
    const double distance = 2.0 + i;
    const RayCaster caster(FacingPlane(distance));
    const Renderer renderer(caster, texture, camera, water);
    const cv::Mat image = renderer.Render(Rigid3d(), 1, 0, frame).image;
    const LaserSpotTruth truth =
        TrueLaserSpot(caster, camera, Rigid3d(), laser);
    Centroid(image, 2, truth.pixel, 10.0, &sums[i]);
    // Per pixel, a white-ish surface's radiance does not depend on range,
    // so the sum over the spot's pixels scales with the spot's area in
    // pixels, 1/d^2, times the beam's power that arrives.
    sums[i] *= distance * distance;
  }
  EXPECT_NEAR(sums[1] / sums[0], std::exp(-0.3 * 2.0), 0.02);
}

TEST(RendererLasers, FrameGainScalesLevelsAndBadFramesAreRejected) {
  const RayCaster caster(FacingPlane(2.0));
  const ConstantTexture texture(Eigen::Vector3f(0.3f, 0.3f, 0.3f));
  RenderOptions options = CleanOptions();
  options.light.intensity = 1.0;
  const Renderer renderer(caster, texture, Pinhole(64, 48, 60), options);
  FrameOptions brighter;
  brighter.gain_factor = 1.5;
  const cv::Mat base = renderer.Render(Rigid3d(), 1, 0).image;
  const cv::Mat gained = renderer.Render(Rigid3d(), 1, 0, brighter).image;
  const double ratio = cv::sum(gained)[0] / cv::sum(base)[0];
  EXPECT_NEAR(ratio, 1.5, 0.01);
  brighter.gain_factor = 0.0;
  EXPECT_THROW(renderer.Render(Rigid3d(), 1, 0, brighter), Error);
  FrameOptions bad_optics;
  bad_optics.optics.waist_radius_m = -1.0;
  EXPECT_THROW(renderer.Render(Rigid3d(), 1, 0, bad_optics), Error);
}

}  // namespace
}  // namespace uw::sim
