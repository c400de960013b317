#include "colmap_plugins/dense/plane_sweep.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "common/util/error.h"
#include "common/util/error_testing.h"
#include "common/util/random.h"

namespace uw {
namespace {

constexpr int kWidth = 200;
constexpr int kHeight = 150;

// Value noise: hashed lattice values in [-1, 1] every kLattice metres,
// smoothed by the cubic B-spline. Unlike a sum of a few sinusoids it has no
// long-range self-similarity, so that a window matches only where it
// should; the B-spline makes it smooth (C2) with little content below two
// lattice spacings, 5 px at 4 m with the 200 px focal length below, above
// the 2 px Nyquist wavelength of point sampling.
constexpr double kLattice = 0.05;

double LatticeValue(int64_t i, int64_t j) {
  const uint64_t key = (static_cast<uint64_t>(i) << 32) ^
                       static_cast<uint64_t>(static_cast<uint32_t>(j));
  return static_cast<double>(SplitMix64(key) >> 11) * 0x1.0p-52 - 1.0;
}

// Weights of the cubic B-spline at the lattice points floor(s) - 1 ... + 2.
std::array<double, 4> BSplineWeights(double f) {
  return {(1 - f) * (1 - f) * (1 - f) / 6.0,
          (3 * f * f * f - 6 * f * f + 4) / 6.0,
          (-3 * f * f * f + 3 * f * f + 3 * f + 1) / 6.0, f * f * f / 6.0};
}

// A plane n . x = offset in the world, textured with value noise: grey in
// 0.5 +- 0.45 (the weights are positive and sum to 1).
struct TexturedPlane {
  Eigen::Vector3d normal_in_world;
  double offset = 0.0;
  Eigen::Vector3d origin_in_world;  // on the plane: texture coordinate (0, 0)
  Eigen::Vector3d axis_u, axis_v;   // orthonormal, in the plane

  double Grey(const Eigen::Vector3d& point_in_world) const {
    const double s = (point_in_world - origin_in_world).dot(axis_u) / kLattice;
    const double t = (point_in_world - origin_in_world).dot(axis_v) / kLattice;
    const double i0 = std::floor(s);
    const double j0 = std::floor(t);
    const std::array<double, 4> wu = BSplineWeights(s - i0);
    const std::array<double, 4> wv = BSplineWeights(t - j0);
    double noise = 0.0;
    for (int a = 0; a < 4; ++a) {
      for (int b = 0; b < 4; ++b) {
        noise += wu[a] * wv[b] *
                 LatticeValue(static_cast<int64_t>(i0) - 1 + a,
                              static_cast<int64_t>(j0) - 1 + b);
      }
    }
    return 0.5 + 0.45 * noise;
  }
};

TexturedPlane MakePlane(const Eigen::Vector3d& point_in_world,
                        const Eigen::Vector3d& normal_in_world) {
  TexturedPlane plane;
  plane.normal_in_world = normal_in_world.normalized();
  plane.offset = plane.normal_in_world.dot(point_in_world);
  plane.origin_in_world = point_in_world;
  plane.axis_u = plane.normal_in_world.unitOrthogonal();
  plane.axis_v = plane.normal_in_world.cross(plane.axis_u);
  return plane;
}

Eigen::Matrix3d Intrinsics() {
  Eigen::Matrix3d K;
  K << 200.0, 0.0, 99.5, 0.0, 200.0, 74.5, 0.0, 0.0, 1.0;
  return K;
}

// The reference camera is placed arbitrarily in the world, so that the
// sweep has to compose real poses; the scene is described in its frame.
Rigid3d WorldFromRef() {
  Rigid3d world_from_ref;
  world_from_ref.rotation = Eigen::Quaterniond(
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  world_from_ref.translation = Eigen::Vector3d(12.0, -5.0, 30.0);
  return world_from_ref;
}

// A camera at `centre_in_ref` looking at `target_in_ref`, y axis down.
Rigid3d CamFromWorldLookingAt(const Eigen::Vector3d& centre_in_ref,
                              const Eigen::Vector3d& target_in_ref) {
  const Eigen::Vector3d z = (target_in_ref - centre_in_ref).normalized();
  const Eigen::Vector3d x = Eigen::Vector3d::UnitY().cross(z).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d ref_from_cam_rotation;
  ref_from_cam_rotation << x, y, z;
  const Rigid3d world_from_ref = WorldFromRef();
  Rigid3d world_from_cam;
  world_from_cam.rotation = Eigen::Quaterniond(world_from_ref.RotationMatrix() *
                                               ref_from_cam_rotation);
  world_from_cam.translation = world_from_ref * centre_in_ref;
  return world_from_cam.Inverse();
}

// Ray-plane intersection at every pixel centre (OpenCV convention).
PinholeView Render(const TexturedPlane& plane, const Rigid3d& cam_from_world) {
  PinholeView view;
  view.K = Intrinsics();
  view.cam_from_world = cam_from_world;
  view.grey.create(kHeight, kWidth, CV_32F);
  const Rigid3d world_from_cam = cam_from_world.Inverse();
  const Eigen::Matrix3d world_from_cam_rotation =
      world_from_cam.RotationMatrix();
  const Eigen::Vector3d centre = world_from_cam.translation;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const Eigen::Vector3d ray =
          world_from_cam_rotation * view.CamFromPixel(x, y, 1.0);
      const double t = (plane.offset - plane.normal_in_world.dot(centre)) /
                       plane.normal_in_world.dot(ray);
      view.grey.at<float>(y, x) =
          static_cast<float>(plane.Grey(centre + t * ray));
    }
  }
  return view;
}

// The reference's true depth at pixel (x, y).
double TrueDepth(const TexturedPlane& plane, const PinholeView& reference,
                 int x, int y) {
  const Rigid3d world_from_ref = reference.cam_from_world.Inverse();
  const Eigen::Vector3d ray =
      world_from_ref.RotationMatrix() * reference.CamFromPixel(x, y, 1.0);
  const Eigen::Vector3d centre = world_from_ref.translation;
  return (plane.offset - plane.normal_in_world.dot(centre)) /
         plane.normal_in_world.dot(ray);
}

struct Scene {
  TexturedPlane plane;
  PinholeView reference;
  std::vector<PinholeView> sources;

  std::vector<const PinholeView*> SourcePointers() const {
    std::vector<const PinholeView*> pointers;
    for (const PinholeView& source : sources) {
      pointers.push_back(&source);
    }
    return pointers;
  }
};

// Reference at the origin of its frame looking along +z at a plane through
// (0, 0, 4) whose normal is tilted by `tilt_deg` about the y axis; four
// sources 1 m (left, right) and 0.8 m (up, down) away, converging on that
// point: baseline / depth 0.2-0.25.
Scene MakeScene(double tilt_deg) {
  const Eigen::Vector3d target_in_ref(0.0, 0.0, 4.0);
  const double tilt = tilt_deg * M_PI / 180.0;
  const Eigen::Vector3d normal_in_ref(std::sin(tilt), 0.0, -std::cos(tilt));
  const Rigid3d world_from_ref = WorldFromRef();
  Scene scene;
  scene.plane = MakePlane(world_from_ref * target_in_ref,
                          world_from_ref.RotationMatrix() * normal_in_ref);
  scene.reference = Render(scene.plane, world_from_ref.Inverse());
  for (const Eigen::Vector3d& centre_in_ref :
       {Eigen::Vector3d(-1.0, 0.0, 0.0), Eigen::Vector3d(1.0, 0.0, 0.0),
        Eigen::Vector3d(0.0, -0.8, 0.0), Eigen::Vector3d(0.0, 0.8, 0.0)}) {
    scene.sources.push_back(Render(
        scene.plane, CamFromWorldLookingAt(centre_in_ref, target_in_ref)));
  }
  return scene;
}

// Where the source sees the reference's pixel (x, y): the true surface point
// lands at least `margin` pixels inside the source image.
bool SourceSees(const Scene& scene, const PinholeView& source, int x, int y,
                int margin) {
  const double depth = TrueDepth(scene.plane, scene.reference, x, y);
  const Eigen::Vector3d point_in_world =
      scene.reference.cam_from_world.Inverse() *
      scene.reference.CamFromPixel(x, y, depth);
  const Eigen::Vector3d point_in_source =
      source.cam_from_world * point_in_world;
  if (point_in_source.z() <= 0.0) {
    return false;
  }
  const Eigen::Vector2d pixel = source.PixelFromCam(point_in_source);
  return pixel.x() >= margin && pixel.y() >= margin &&
         pixel.x() <= kWidth - 1 - margin && pixel.y() <= kHeight - 1 - margin;
}

struct DepthErrors {
  int num_pixels = 0;        // counted pixels
  int num_depths = 0;        // ... with a depth
  int num_accurate = 0;      // ... within the tolerance of the truth
  int num_wrong = 0;         // ... off by more than 1 %
  int num_out_of_range = 0;  // depths outside [min_depth, max_depth]
};

// Pixels at least the window radius (3) from the border, and among them
// those `counted` accepts.
DepthErrors CompareDepths(
    const Scene& scene, const DepthMap& result, double min_depth,
    double max_depth, double relative_tolerance,
    const std::function<bool(int, int)>& counted = [](int, int) {
      return true;
    }) {
  DepthErrors errors;
  for (int y = 3; y < kHeight - 3; ++y) {
    for (int x = 3; x < kWidth - 3; ++x) {
      if (!counted(x, y)) {
        continue;
      }
      ++errors.num_pixels;
      const double depth = result.depth.at<float>(y, x);
      if (depth <= 0.0) {
        continue;
      }
      ++errors.num_depths;
      if (depth < min_depth || depth > max_depth) {
        ++errors.num_out_of_range;
      }
      const double truth = TrueDepth(scene.plane, scene.reference, x, y);
      const double error = std::abs(depth - truth) / truth;
      if (error <= relative_tolerance) {
        ++errors.num_accurate;
      }
      if (error > 0.01) {
        ++errors.num_wrong;
      }
    }
  }
  return errors;
}

// 0.3 % of 4 m is 12 mm, a disparity of 0.15 px over the 1 m baseline.
constexpr double kTolerance = 0.003;

TEST(PlaneSweepDepth, FrontoParallelPlane) {
  const Scene scene = MakeScene(0.0);
  const PlaneSweepOptions options;
  const DepthMap result = PlaneSweepDepth(
      scene.reference, scene.SourcePointers(), 2.5, 7.0, options);
  ASSERT_EQ(result.depth.type(), CV_32F);
  ASSERT_EQ(result.cost.type(), CV_32F);
  ASSERT_EQ(result.depth.size(), scene.reference.grey.size());
  // Inverse depths 1/7 .. 1/2.5 in steps of at most 1 px of the largest
  // baseline (~1 m at 200 px): about 0.257 * 200 planes.
  EXPECT_GE(result.num_planes, 45);
  EXPECT_LE(result.num_planes, 70);
  // Measured: 99.7 % within 0.3 %, none off by more than 1 %.
  const DepthErrors errors = CompareDepths(scene, result, 2.5, 7.0, kTolerance);
  EXPECT_GE(errors.num_accurate, 0.99 * errors.num_pixels)
      << errors.num_accurate << " of " << errors.num_pixels;
  EXPECT_EQ(errors.num_wrong, 0);
  EXPECT_EQ(errors.num_out_of_range, 0);
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      if (result.depth.at<float>(y, x) > 0.0f) {
        ASSERT_LE(result.cost.at<float>(y, x), options.max_cost);
        ASSERT_GE(result.cost.at<float>(y, x), 0.0f);
      } else {
        ASSERT_EQ(result.cost.at<float>(y, x), 0.0f);
      }
    }
  }
}

TEST(PlaneSweepDepth, PlaneTiltedByTwentyDegrees) {
  const Scene scene = MakeScene(20.0);
  // Depths from 3.4 m (left) to 4.9 m (right).
  ASSERT_LT(TrueDepth(scene.plane, scene.reference, 0, 75), 3.4);
  ASSERT_GT(TrueDepth(scene.plane, scene.reference, 199, 75), 4.8);
  const DepthMap result = PlaneSweepDepth(
      scene.reference, scene.SourcePointers(), 2.5, 7.0, PlaneSweepOptions());
  // The fronto-parallel windows straddle depths that differ by 1.3 % here,
  // so the tilt costs some accuracy. Measured: 98.4 % within 0.3 %, none
  // off by more than 1 %.
  const DepthErrors errors = CompareDepths(scene, result, 2.5, 7.0, kTolerance);
  EXPECT_GE(errors.num_accurate, 0.95 * errors.num_pixels)
      << errors.num_accurate << " of " << errors.num_pixels;
  EXPECT_EQ(errors.num_wrong, 0);
  EXPECT_EQ(errors.num_out_of_range, 0);
}

TEST(PlaneSweepDepth, SingleSourceStillGivesDepths) {
  const Scene scene = MakeScene(0.0);
  const PinholeView& right = scene.sources[1];
  const DepthMap result =
      PlaneSweepDepth(scene.reference, {&right}, 2.5, 7.0, PlaneSweepOptions());
  // Where the source sees the window of the reference pixel. Measured:
  // 97.5 % within 0.3 %, 4 of 26480 pixels off by more than 1 %.
  const DepthErrors errors = CompareDepths(
      scene, result, 2.5, 7.0, kTolerance,
      [&](int x, int y) { return SourceSees(scene, right, x, y, 4); });
  EXPECT_GT(errors.num_pixels, 0.8 * (kWidth - 6) * (kHeight - 6));
  EXPECT_GE(errors.num_accurate, 0.95 * errors.num_pixels)
      << errors.num_accurate << " of " << errors.num_pixels;
  EXPECT_LE(errors.num_wrong, 0.002 * errors.num_pixels)
      << errors.num_wrong << " of " << errors.num_pixels;
}

TEST(PlaneSweepDepth, MinimumAtTheEndOfTheRangeGivesNoDepth) {
  const Scene scene = MakeScene(0.0);
  // The plane at 4 m lies just before the range [4.3, 7]: costs fall
  // towards its nearest plane, which must not be reported as the surface
  // (measured: 4 pixels of 27936 within 4.30-4.35 m). Spurious minima
  // elsewhere in the range are not checked: with 7 x 7 windows some 20 %
  // of the pixels find one below max_cost.
  const DepthMap result = PlaneSweepDepth(
      scene.reference, scene.SourcePointers(), 4.3, 7.0, PlaneSweepOptions());
  const DepthErrors near_end =
      CompareDepths(scene, result, 4.3, 4.35, kTolerance);
  EXPECT_LT(near_end.num_depths - near_end.num_out_of_range,
            0.005 * near_end.num_pixels)
      << near_end.num_depths - near_end.num_out_of_range << " of "
      << near_end.num_pixels;
  EXPECT_EQ(CompareDepths(scene, result, 4.3, 7.0, kTolerance).num_out_of_range,
            0);
}

TEST(PlaneSweepDepth, TexturelessImagesGiveNoDepth) {
  Scene scene = MakeScene(0.0);
  Scene flat = scene;
  flat.reference.grey = cv::Mat(kHeight, kWidth, CV_32F, cv::Scalar(0.5));
  for (PinholeView& source : flat.sources) {
    source.grey = cv::Mat(kHeight, kWidth, CV_32F, cv::Scalar(0.5));
  }
  EXPECT_EQ(
      cv::countNonZero(PlaneSweepDepth(flat.reference, flat.SourcePointers(),
                                       2.5, 7.0, PlaneSweepOptions())
                           .depth),
      0);

  // The reference's texture at 2 % contrast: window deviations below
  // min_texture (0.004), though NCC, blind to contrast, would match it.
  cv::Mat faint = 0.5 + 0.02 * (scene.reference.grey - 0.5);
  scene.reference.grey = faint;
  EXPECT_EQ(
      cv::countNonZero(PlaneSweepDepth(scene.reference, scene.SourcePointers(),
                                       2.5, 7.0, PlaneSweepOptions())
                           .depth),
      0);
  PlaneSweepOptions lenient;
  lenient.min_texture = 1e-4;
  const DepthErrors errors =
      CompareDepths(scene,
                    PlaneSweepDepth(scene.reference, scene.SourcePointers(),
                                    2.5, 7.0, lenient),
                    2.5, 7.0, kTolerance);
  EXPECT_GE(errors.num_accurate, 0.99 * errors.num_pixels)
      << errors.num_accurate << " of " << errors.num_pixels;
}

TEST(PlaneSweepDepth, InvalidInputsThrow) {
  PinholeView view;
  view.grey = cv::Mat(20, 20, CV_32F, cv::Scalar(0.5));
  const PlaneSweepOptions options;
  ExpectErrorContaining([&] { PlaneSweepDepth(view, {}, 1.0, 2.0, options); },
                        "1 to 16 source images, got 0");
  const std::vector<const PinholeView*> seventeen(17, &view);
  ExpectErrorContaining(
      [&] { PlaneSweepDepth(view, seventeen, 1.0, 2.0, options); },
      "1 to 16 source images, got 17");
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const auto& [min_depth, max_depth] :
       std::vector<std::pair<double, double>>{{0.0, 2.0},
                                              {-1.0, 2.0},
                                              {2.0, 2.0},
                                              {3.0, 2.0},
                                              {1.0, inf},
                                              {nan, 2.0},
                                              {1.0, nan}}) {
    ExpectErrorContaining(
        [&] { PlaneSweepDepth(view, {&view}, min_depth, max_depth, options); },
        "0 < min_depth < max_depth");
  }
}

TEST(PlaneSweepOptions, CheckRejectsBadFields) {
  EXPECT_NO_THROW(PlaneSweepOptions().Check());
  const std::vector<
      std::pair<std::function<void(PlaneSweepOptions*)>, std::string>>
      cases = {
          {[](PlaneSweepOptions* o) { o->window_radius = 0; }, "window_radius"},
          {[](PlaneSweepOptions* o) { o->plane_step_px = 0.0; },
           "plane_step_px"},
          {[](PlaneSweepOptions* o) { o->num_best_sources = 0; },
           "num_best_sources"},
          {[](PlaneSweepOptions* o) { o->max_cost = 0.0; }, "max_cost"},
          {[](PlaneSweepOptions* o) { o->max_cost = 2.5; }, "max_cost"},
          {[](PlaneSweepOptions* o) { o->min_texture = -0.1; }, "min_texture"},
      };
  PinholeView view;
  view.grey = cv::Mat(20, 20, CV_32F, cv::Scalar(0.5));
  for (const auto& [spoil, field] : cases) {
    PlaneSweepOptions options;
    spoil(&options);
    ExpectErrorContaining([&] { options.Check(); }, field);
    ExpectErrorContaining(
        [&] { PlaneSweepDepth(view, {&view}, 1.0, 2.0, options); }, field);
  }
}

}  // namespace
}  // namespace uw
