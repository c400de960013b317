#include "colmap_plugins/dense/view_selection.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>

#include "common/util/error.h"
#include "common/util/error_testing.h"

namespace uw {
namespace {

constexpr double kHeight = 10.0;

double SeafloorZ(double x, double y) {
  return 0.3 * std::sin(1.3 * x + 0.7 * y);
}

// Seven images 10 m above a gently undulating seafloor, looking straight
// down, their centres on the x axis:
//   index 0..4 at x = 0, 0.3, 1.5, 3, 5 see the points with |x - x_c| <= 3 of
//     a 0.25 m grid over x in [-4, 8], y in [-2, 2];
//   index 5 at x = 6.5 sees only 20 of them (x in [6, 6.75], |y| <= 0.5),
//     5 of which image 3 sees as well;
//   index 6 at x = 30 sees 9 points nobody else sees.
// Shared points, median triangulation angles (deg) and the documented score
// shared * min(1, angle / 10), computed independently of the library:
//   (0,1) 391  1.65 (below 3)   (1,2) 340  6.68 227.1   (2,4) 187 19.38 187
//   (0,2) 323  8.38 270.8       (1,3) 238 15.26 238     (3,4) 289 11.15 289
//   (0,3) 221 16.99 221         (1,4) 102 26.09 102     (3,5)   5 20.12   5
//   (0,4)  85 27.89  85         (2,3) 323  8.35 269.8   (4,5)  20  8.76  17.5
const std::vector<double> kCentreX = {0.0, 0.3, 1.5, 3.0, 5.0, 6.5, 30.0};

image_t ImageId(size_t index) { return static_cast<image_t>(101 + 10 * index); }

Reconstruction MakeModel() {
  Reconstruction model;
  Camera camera;
  camera.camera_id = 1;
  camera.model_id = CameraModelId::kPinhole;
  camera.width = 640;
  camera.height = 480;
  camera.params = {500.0, 500.0, 320.0, 240.0};
  model.AddCamera(camera);

  // Looking down: x_cam = x, y_cam = -y, z_cam = -z (180 deg about x).
  const Eigen::Quaterniond cam_from_world_rotation(0.0, 1.0, 0.0, 0.0);
  std::vector<Image> images(kCentreX.size());
  for (size_t i = 0; i < images.size(); ++i) {
    images[i].image_id = ImageId(i);
    images[i].camera_id = 1;
    images[i].name = "img_" + std::to_string(i) + ".png";
    images[i].cam_from_world.rotation = cam_from_world_rotation;
    images[i].cam_from_world.translation =
        -(cam_from_world_rotation * Eigen::Vector3d(kCentreX[i], 0.0, kHeight));
  }

  point3D_t next_id = 1;
  auto add_point = [&](const Eigen::Vector3d& xyz,
                       const std::vector<size_t>& seen_by) {
    Point3D point;
    point.point3D_id = next_id++;
    point.xyz = xyz;
    for (const size_t i : seen_by) {
      Image& image = images[i];
      Point2D observation;
      const Eigen::Vector3d point_in_cam = image.cam_from_world * xyz;
      observation.xy = camera.ImgFromCam(point_in_cam);
      observation.point3D_id = point.point3D_id;
      point.track.push_back(
          {image.image_id, static_cast<point2D_t>(image.points2D.size())});
      image.points2D.push_back(observation);
    }
    model.AddPoint3D(point);
  };
  for (int ix = 0; ix <= 48; ++ix) {
    for (int iy = 0; iy <= 16; ++iy) {
      const double x = -4.0 + 0.25 * ix;
      const double y = -2.0 + 0.25 * iy;
      std::vector<size_t> seen_by;
      for (size_t i = 0; i < 5; ++i) {
        if (std::abs(x - kCentreX[i]) <= 3.0 + 1e-9) {
          seen_by.push_back(i);
        }
      }
      if (x > 5.99 && x < 6.8 && std::abs(y) <= 0.51) {
        seen_by.push_back(5);
      }
      if (!seen_by.empty()) {
        add_point(Eigen::Vector3d(x, y, SeafloorZ(x, y)), seen_by);
      }
    }
  }
  for (int k = 0; k < 9; ++k) {
    add_point(Eigen::Vector3d(30.0 + 0.25 * (k % 3), 0.25 * (k / 3), 0.0), {6});
  }
  for (Image& image : images) {
    model.AddImage(image);
  }
  model.Check("synthetic model");
  return model;
}

// True depths of the points an image sees: the camera looks straight down
// from kHeight.
std::vector<double> TrueDepths(const Reconstruction& model, size_t index) {
  std::vector<double> depths;
  for (const Point3D& point : model.Points3D()) {
    for (const TrackElement& element : point.track) {
      if (element.image_id == ImageId(index)) {
        depths.push_back(kHeight - point.xyz.z());
      }
    }
  }
  std::sort(depths.begin(), depths.end());
  return depths;
}

using Neighbors = std::vector<size_t>;

TEST(SelectViews, RanksOverlappingPairsBySharedPointsAndAngle) {
  const Reconstruction model = MakeModel();
  const std::vector<ViewNeighbors> views =
      SelectViews(model, ViewSelectionOptions());
  ASSERT_EQ(views.size(), 7u);
  // Image 1 shares the most points with image 0 but at 1.7 deg; image 3
  // beats image 2 for image 1 despite fewer shared points (238 vs 340)
  // because the pair (1, 2) sees them under 6.7 deg only.
  EXPECT_EQ(views[0].neighbors, (Neighbors{2, 3, 4}));
  EXPECT_EQ(views[1].neighbors, (Neighbors{3, 2, 4}));
  EXPECT_EQ(views[2].neighbors, (Neighbors{0, 3, 1, 4}));
  EXPECT_EQ(views[3].neighbors, (Neighbors{4, 2, 1, 0}));
  // Image 5 shares 20 points with image 4 and 5 with image 3: below the
  // default 30.
  EXPECT_EQ(views[4].neighbors, (Neighbors{3, 2, 1, 0}));
  EXPECT_TRUE(views[5].neighbors.empty());
  EXPECT_TRUE(views[6].neighbors.empty());
  for (size_t i = 0; i < views.size(); ++i) {
    EXPECT_EQ(
        std::count(views[i].neighbors.begin(), views[i].neighbors.end(), i), 0)
        << "image " << i << " is its own neighbour";
  }
}

TEST(SelectViews, OptionsMoveTheThresholds) {
  const Reconstruction model = MakeModel();
  ViewSelectionOptions options;
  options.num_neighbors = 2;
  EXPECT_EQ(SelectViews(model, options)[2].neighbors, (Neighbors{0, 3}));
  EXPECT_EQ(SelectViews(model, options)[3].neighbors, (Neighbors{4, 2}));

  // Below 1.65 deg the near-duplicate image 1 is admitted, last (64.6).
  options = ViewSelectionOptions();
  options.min_triangulation_angle_deg = 1.0;
  EXPECT_EQ(SelectViews(model, options)[0].neighbors, (Neighbors{2, 3, 4, 1}));

  // (0, 4) at 27.9 deg and (1, 4) at 26.1 deg go; (2, 4) at 19.4 deg stays.
  options = ViewSelectionOptions();
  options.max_triangulation_angle_deg = 20.0;
  const std::vector<ViewNeighbors> narrow = SelectViews(model, options);
  EXPECT_EQ(narrow[0].neighbors, (Neighbors{2, 3}));
  EXPECT_EQ(narrow[4].neighbors, (Neighbors{3, 2}));

  // 20 shared points are enough now for (4, 5), but not the 5 of (3, 5).
  options = ViewSelectionOptions();
  options.min_shared_points = 20;
  options.num_neighbors = 5;
  const std::vector<ViewNeighbors> loose = SelectViews(model, options);
  EXPECT_EQ(loose[4].neighbors, (Neighbors{3, 2, 1, 0, 5}));
  EXPECT_EQ(loose[5].neighbors, (Neighbors{4}));
}

TEST(SelectViews, DepthRangeHoldsTheTrueDepthsWithTheMargin) {
  const Reconstruction model = MakeModel();
  ViewSelectionOptions options;
  options.depth_quantile = 0.0;
  options.depth_margin = 0.15;
  const std::vector<ViewNeighbors> exact = SelectViews(model, options);
  const std::vector<ViewNeighbors> defaults =
      SelectViews(model, ViewSelectionOptions());
  for (size_t i = 0; i < 6; ++i) {
    SCOPED_TRACE("image " + std::to_string(i));
    const std::vector<double> depths = TrueDepths(model, i);
    ASSERT_GE(depths.size(), 20u);
    ASSERT_TRUE(exact[i].depth_range.has_value());
    EXPECT_NEAR(exact[i].depth_range->first, 0.85 * depths.front(), 1e-12);
    EXPECT_NEAR(exact[i].depth_range->second, 1.15 * depths.back(), 1e-12);

    // Quantiles 2 % and 98 %: inside the extremes, and the 15 % margin still
    // spans every true depth here (they vary by +-3 %).
    ASSERT_TRUE(defaults[i].depth_range.has_value());
    const auto [near, far] = *defaults[i].depth_range;
    EXPECT_GE(near, 0.85 * depths.front());
    EXPECT_LE(far, 1.15 * depths.back());
    EXPECT_LT(near, depths.front());
    EXPECT_GT(far, depths.back());
  }
  // Nine points are too few for a range.
  EXPECT_FALSE(exact[6].depth_range.has_value());
  EXPECT_FALSE(defaults[6].depth_range.has_value());
}

TEST(SelectViews, QuantilesTrimTheDepthRange) {
  const Reconstruction model = MakeModel();
  ViewSelectionOptions options;
  options.depth_quantile = 0.25;
  options.depth_margin = 0.0;
  const std::vector<ViewNeighbors> views = SelectViews(model, options);
  for (size_t i = 0; i < 6; ++i) {
    SCOPED_TRACE("image " + std::to_string(i));
    const std::vector<double> depths = TrueDepths(model, i);
    ASSERT_TRUE(views[i].depth_range.has_value());
    const auto [near, far] = *views[i].depth_range;
    EXPECT_GT(near, depths.front());
    EXPECT_LT(far, depths.back());
    const auto inside = std::count_if(depths.begin(), depths.end(),
                                      [near = near, far = far](double depth) {
                                        return depth >= near && depth <= far;
                                      });
    // The central half, to one rank.
    EXPECT_NEAR(static_cast<double>(inside) / depths.size(), 0.5,
                2.0 / depths.size());
  }
}

TEST(ViewSelectionOptions, CheckRejectsBadFields) {
  EXPECT_NO_THROW(ViewSelectionOptions().Check());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<
      std::pair<std::function<void(ViewSelectionOptions*)>, std::string>>
      cases = {
          {[](ViewSelectionOptions* o) { o->num_neighbors = 0; },
           "num_neighbors"},
          {[](ViewSelectionOptions* o) { o->num_neighbors = 17; },
           "num_neighbors"},
          {[](ViewSelectionOptions* o) { o->min_shared_points = 0; },
           "min_shared_points"},
          {[](ViewSelectionOptions* o) { o->min_triangulation_angle_deg = -1; },
           "triangulation angles"},
          {[](ViewSelectionOptions* o) {
             o->min_triangulation_angle_deg = 45.0;
           },
           "triangulation angles"},
          {[](ViewSelectionOptions* o) {
             o->max_triangulation_angle_deg = 181.0;
           },
           "triangulation angles"},
          {[nan](ViewSelectionOptions* o) {
             o->min_triangulation_angle_deg = nan;
           },
           "triangulation angles"},
          {[](ViewSelectionOptions* o) { o->depth_quantile = 0.5; },
           "depth_quantile"},
          {[](ViewSelectionOptions* o) { o->depth_quantile = -0.01; },
           "depth_quantile"},
          {[](ViewSelectionOptions* o) { o->depth_margin = 1.0; },
           "depth_margin"},
          {[nan](ViewSelectionOptions* o) { o->depth_margin = nan; },
           "depth_margin"},
      };
  const Reconstruction model = MakeModel();
  for (const auto& [spoil, field] : cases) {
    ViewSelectionOptions options;
    spoil(&options);
    ExpectErrorContaining([&] { options.Check(); }, field);
    ExpectErrorContaining([&] { SelectViews(model, options); }, field);
  }
}

}  // namespace
}  // namespace uw
