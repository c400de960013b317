#include "colmap_plugins/ba/lcurve.h"

#include <cmath>
#include <filesystem>
#include <iostream>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "colmap_plugins/ba/test_scene.h"
#include "common/util/error.h"
#include "common/util/file.h"
#include "tests/support/svg_ticks.h"

namespace uw {
namespace {

// A curve with a known corner, in log10 coordinates: down the line x = 0
// from y = 2 to y = r, a quarter circle of radius r to (r, 0), then right
// to x = 2; lambda = exp(arc length). The corner is the arc's middle.
constexpr double kArcRadius = 0.2;

LCurvePoint ArcPoint(double lambda) {
  const double length = std::log(lambda);
  const double straight = 2.0 - kArcRadius;
  const double arc = 0.5 * M_PI * kArcRadius;
  double x;
  double y;
  if (length < straight) {
    x = 0.0;
    y = 2.0 - length;
  } else if (length < straight + arc) {
    const double angle = (length - straight) / kArcRadius;  // 0 .. pi/2
    x = kArcRadius - kArcRadius * std::cos(angle);
    y = kArcRadius - kArcRadius * std::sin(angle);
  } else {
    x = kArcRadius + (length - straight - arc);
    y = 0.0;
  }
  LCurvePoint point;
  point.weight_px_per_m = lambda;
  point.reprojection_ms_px2 = std::pow(10.0, x);
  point.navigation_ms_m2 = std::pow(10.0, y);
  return point;
}

TEST(LCurve, FindsTheCornerOfAKnownCurve) {
  const double total = 2.0 * (2.0 - kArcRadius) + 0.5 * M_PI * kArcRadius;
  const double exact = std::exp(2.0 - kArcRadius + 0.25 * M_PI * kArcRadius);
  std::vector<LCurvePoint> points;
  for (const double lambda : LogSpacedWeights(1.0, std::exp(total), 30)) {
    points.push_back(ArcPoint(lambda));
  }
  const LCurve curve = FindLCurveCorner(points);
  std::cout << "[ figures ] known corner lambda " << exact << ", found "
            << curve.corner_weight_px_per_m.value_or(NAN)
            << " from 30 points\n";
  ASSERT_TRUE(curve.corner_weight_px_per_m.has_value());
  EXPECT_NEAR(std::log(*curve.corner_weight_px_per_m), std::log(exact), 0.05);
  // The curve without its descending branch has no corner.
  std::vector<LCurvePoint> no_corner;
  for (const LCurvePoint& point : points) {
    if (point.navigation_ms_m2 < 1.0001) no_corner.push_back(point);
  }
  no_corner.erase(no_corner.begin(), no_corner.begin() + 3);
  EXPECT_FALSE(FindLCurveCorner(no_corner).corner_weight_px_per_m.has_value());
}

TEST(LCurve, RejectsBadInput) {
  EXPECT_THROW(LogSpacedWeights(0.0, 1.0, 10), Error);
  EXPECT_THROW(LogSpacedWeights(1.0, 10.0, 3), Error);
  std::vector<LCurvePoint> points;
  for (const double lambda : LogSpacedWeights(1.0, 40.0, 6)) {
    points.push_back(ArcPoint(lambda));
  }
  std::vector<LCurvePoint> zero = points;
  zero[2].navigation_ms_m2 = 0.0;
  EXPECT_THROW(FindLCurveCorner(zero), Error);
  std::vector<LCurvePoint> unsorted = points;
  std::swap(unsorted[1], unsorted[3]);
  EXPECT_THROW(FindLCurveCorner(unsorted), Error);
  points.resize(4);
  EXPECT_THROW(FindLCurveCorner(points), Error);
}

// Both figures are written, with axes a reader can read: decades or 1-2-5
// steps, whatever the curve's span.
TEST(LCurve, FiguresAndJsonAreWritten) {
  std::vector<LCurvePoint> points;
  for (const double lambda : LogSpacedWeights(1.0, 40.0, 15)) {
    points.push_back(ArcPoint(lambda));
  }
  const LCurve curve = FindLCurveCorner(points);
  // Reprojection mean squares within less than a decade (a log axis
  // without a power of ten on it).
  LCurve narrow = curve;
  for (size_t i = 0; i < narrow.points.size(); ++i) {
    narrow.points[i].reprojection_ms_px2 = 0.25 + 0.01 * i;
  }
  const LCurve* const curves[] = {&curve, &narrow};
  for (const LCurve* c : curves) {
    const std::filesystem::path folder =
        std::filesystem::path(testing::TempDir()) / "uw_lcurve_test";
    std::filesystem::remove_all(folder);
    WriteFigures(LCurveFigures(*c), LCurveFigurePaths(folder));
    for (const char* name : {"lcurve", "lcurve_curvature"}) {
      EXPECT_FALSE(
          cv::imread((folder / (std::string(name) + ".png")).string()).empty());
      const std::string svg =
          ReadFileToString(folder / (std::string(name) + ".svg"));
      for (const char axis : {'x', 'y'}) {
        EXPECT_EQ(TickProblem(SvgTickLabels(svg, axis)), "")
            << name << " " << axis;
      }
    }
  }
  EXPECT_NE(LCurveJson(curve).find("corner_weight_px_per_m"),
            std::string::npos);
}

// Acceptance 2 of issue 4 for the L-curve's balance point (--Nav.weight
// balance; auto is tested in noise_levels_test.cc): with known pixel noise
// sigma_v and navigation noise sigma_n it lies within a factor 1.5 of
// sigma_v / sigma_n, under the default (likelihood) weighting. Under
// Eq. 2's weighting the 5 cm case has no balance point.
TEST(LCurve, BalancePointIsTheRatioOfTheNoiseLevels) {
  for (const auto& [pixel_sigma, nav_sigma] :
       std::vector<std::pair<double, double>>{
           {0.5, 0.3}, {0.5, 0.1}, {1.0, 0.05}}) {
    test::TestSceneOptions scene_options;
    scene_options.num_lines = 2;
    scene_options.images_per_line = 10;
    scene_options.num_points = 800;
    scene_options.pixel_sigma = pixel_sigma;
    scene_options.nav_sigma_m = nav_sigma;
    const test::TestScene scene = test::MakeTestScene(scene_options);
    const NavBundleAdjustmentOptions options = test::FixedIntrinsics();
    const double ratio = pixel_sigma / nav_sigma;
    const LCurve curve =
        SweepLCurve(options, scene.priors, nullptr, {}, scene.observed,
                    LogSpacedWeights(ratio / 5.0, ratio * 5.0, 11));
    for (const LCurvePoint& p : curve.points) {
      std::cout << "    lambda " << p.weight_px_per_m << ": rho "
                << p.reprojection_ms_px2 << " px^2, eta " << p.navigation_ms_m2
                << " m^2\n";
    }
    ASSERT_TRUE(curve.balance_weight_px_per_m.has_value());
    std::cout << "[ figures ] sigma_v " << pixel_sigma << " px, sigma_n "
              << nav_sigma << " m (sigma_v/sigma_n " << ratio
              << " px/m): balance lambda " << *curve.balance_weight_px_per_m
              << " (x" << *curve.balance_weight_px_per_m / ratio
              << "), max-curvature corner "
              << curve.corner_weight_px_per_m.value_or(NAN) << "\n";
    EXPECT_LT(std::abs(std::log(*curve.balance_weight_px_per_m / ratio)),
              std::log(1.5));
  }
}

}  // namespace
}  // namespace uw
