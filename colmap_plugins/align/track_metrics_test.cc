#include "colmap_plugins/align/track_metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "common/util/error.h"

namespace uw {
namespace {

// A single pass: 101 cameras 0.85 m apart along y, weaving a little so the
// centres are not collinear, looking along -x at a wall.
std::vector<Eigen::Vector3d> StraightPass() {
  std::vector<Eigen::Vector3d> centres;
  for (int k = 0; k <= 100; ++k) {
    const double y = 0.85 * k;
    centres.emplace_back(3.0 + 0.15 * std::sin(y / 5.0), y,
                         0.4 * std::sin(y / 3.7));
  }
  return centres;
}

TEST(TrackAxis, PrincipalDirectionFromFirstToLast) {
  std::vector<Eigen::Vector3d> centres = StraightPass();
  std::reverse(centres.begin(), centres.end());
  const TrackAxis axis = TrackAxisFromCentres(centres);
  EXPECT_NEAR(axis.direction.y(), -1.0, 1e-3);
  EXPECT_NEAR(axis.length, 85.0, 0.1);
  EXPECT_NEAR(axis.AlongTrack(centres.front()),
              -axis.AlongTrack(centres.back()), 0.1);
  EXPECT_THROW(TrackAxisFromCentres({{1, 2, 3}}), Error);
  EXPECT_THROW(TrackAxisFromCentres({{1, 2, 3}, {1, 2, 3}}), Error);
}

// A pass 5 cm off its 11 m line is one; a lawnmower of two lines 1 m
// apart, and fewer than 3 centres, are not.
TEST(TrackAxis, DescribesCentresOnOneLine) {
  std::vector<Eigen::Vector3d> pass, lawnmower;
  for (int k = 0; k < 12; ++k) {
    // Signs + - - + + - - ...: no correlation with k, the axis stays x.
    pass.emplace_back(k, k % 4 == 0 || k % 4 == 3 ? 0.05 : -0.05, 0.0);
    lawnmower.emplace_back(k, 0.0, 0.0);
    lawnmower.emplace_back(k, 1.0, 0.0);
  }
  const std::optional<std::string> line = DescribeOneLineTrack(pass);
  ASSERT_TRUE(line);
  EXPECT_EQ(line->rfind("12 camera centres lie nearly on one line (RMS 0.05 "
                        "m across it, 3.45 m along, axis [1.00, ",
                        0),
            0u)
      << *line;
  EXPECT_NE(line->find("]): positions alone fix the model's rotation about "
                       "the line only through that scatter"),
            std::string::npos);
  EXPECT_FALSE(DescribeOneLineTrack(lawnmower));
  EXPECT_FALSE(DescribeOneLineTrack({pass[0], pass[1]}));
}

TEST(PerSegmentScale, UniformlyScaledTrackHasUniformScale) {
  const std::vector<Eigen::Vector3d> reference = StraightPass();
  std::vector<Eigen::Vector3d> track;
  for (const Eigen::Vector3d& centre : reference) {
    track.push_back(Eigen::Vector3d(1, 2, 3) + 0.97 * centre);
  }
  const TrackAxis axis = TrackAxisFromCentres(reference);
  const std::vector<SegmentScale> segments =
      PerSegmentScale(track, reference, {}, {}, axis, 6);
  ASSERT_EQ(segments.size(), 6u);
  size_t num_steps = 0;
  for (const SegmentScale& segment : segments) {
    EXPECT_NEAR(segment.scale_3d, 1.0 / 0.97, 1e-12);
    EXPECT_NEAR(segment.scale_along_track, 1.0 / 0.97, 1e-12);
    EXPECT_NEAR(segment.end - segment.begin, axis.length / 6, 1e-9);
    num_steps += segment.num_steps;
  }
  EXPECT_EQ(num_steps, 100u);
}

// Bending the pass into a circular arc of the same length (what a slightly
// wrong radial distortion does, doming_feasibility.md) keeps 3D distances,
// while the steps projected on the track shorten towards the ends and the
// viewing direction turns with the arc.
TEST(PerSegmentScale, BentTrackKeepsLengthButNotItsProjection) {
  const std::vector<Eigen::Vector3d> reference = StraightPass();
  // Wrapped around a vertical cylinder of radius 150 m whose axis lies on
  // the viewing side: the ends come towards the wall the cameras look at.
  const double radius = 150.0;
  const Eigen::Vector3d axis_point(3.0 - radius, 42.5, 0.0);
  std::vector<Eigen::Vector3d> track;
  std::vector<Eigen::Vector3d> track_views;
  std::vector<Eigen::Vector3d> reference_views;
  for (const Eigen::Vector3d& centre : reference) {
    const double angle = (centre.y() - 42.5) / radius;
    const Eigen::Vector3d radial(std::cos(angle), std::sin(angle), 0.0);
    track.push_back(axis_point + (radius + centre.x() - 3.0) * radial +
                    Eigen::Vector3d(0, 0, centre.z()));
    reference_views.push_back(-Eigen::Vector3d::UnitX());
    track_views.push_back(-radial);
  }
  const TrackAxis axis = TrackAxisFromCentres(reference);
  const std::vector<SegmentScale> segments =
      PerSegmentScale(track, reference, track_views, reference_views, axis, 6);
  for (const SegmentScale& segment : segments) {
    EXPECT_NEAR(segment.scale_3d, 1.0, 2e-3);
  }
  // 1 / cos of the angle: ~1.03 in the end segments (0.24 rad), ~1.002 in
  // the middle ones (0.05 rad).
  EXPECT_GT(segments.front().scale_along_track, 1.02);
  EXPECT_GT(segments.back().scale_along_track, 1.02);
  EXPECT_NEAR(segments[2].scale_along_track, 1.0, 5e-3);
  EXPECT_NEAR(segments[3].scale_along_track, 1.0, 5e-3);
  EXPECT_LT(segments.front().view_tilt_deg, -10.0);
  EXPECT_GT(segments.back().view_tilt_deg, 10.0);
  EXPECT_NEAR(segments.front().view_tilt_deg, -segments.back().view_tilt_deg,
              0.1);
}

TEST(FitDome, RecoversTheSagittaOfAKnownParabola) {
  const double length = 84.0;
  const double c2 = -0.0017;  // sagitta c2 L² / 4 = -3.0 m
  std::mt19937_64 random(3);
  std::uniform_real_distribution<double> uniform(-0.5 * length, 0.5 * length);
  std::normal_distribution<double> noise(0.0, 0.01);
  std::vector<double> xs;
  std::vector<double> ds;
  for (int i = 0; i < 20000; ++i) {
    const double x = uniform(random);
    xs.push_back(x);
    // Also 5 % of points far off the surface, which medians ignore.
    const double outlier = i % 20 == 0 ? 4.0 : 0.0;
    ds.push_back(0.3 + 0.002 * x + c2 * x * x + noise(random) + outlier);
  }
  const std::vector<DeviationBin> bins =
      BinAlongTrack(xs, ds, -0.5 * length, 0.5 * length, 12);
  const DomeFit fit = FitDome(bins, length, 10);
  ASSERT_TRUE(fit.valid);
  EXPECT_EQ(fit.num_bins_used, 12u);
  std::cout << "[ figures ] dome fit: sagitta " << fit.sagitta_m
            << " m (true -2.9988 m), " << fit.sagitta_percent << " % of "
            << length << " m\n";
  EXPECT_NEAR(fit.sagitta_m, c2 * length * length / 4, 0.03);
  EXPECT_NEAR(fit.sagitta_percent, 100 * c2 * length / 4, 0.04);
  EXPECT_NEAR(fit.coefficients[1], 0.002, 3e-4);
  // Too few populated bins: no fit.
  EXPECT_FALSE(FitDome(bins, length, 100000).valid);
}

TEST(CameraDistanceRatios, MeasuresScaleDifferences) {
  const std::vector<Eigen::Vector3d> b = StraightPass();
  std::vector<Eigen::Vector3d> a;
  for (const Eigen::Vector3d& centre : b) a.push_back(1.02 * centre);
  DistanceRatios ratios = CameraDistanceRatios(a, b);
  EXPECT_NEAR(ratios.median_ratio, 1.02, 1e-12);
  EXPECT_NEAR(ratios.max_abs_deviation, 0.02, 1e-12);
  EXPECT_GT(ratios.num_pairs, 4000u);
  a[50].y() += 1.0;
  ratios = CameraDistanceRatios(a, b, 0.1, 51);
  EXPECT_NEAR(ratios.median_ratio, 1.02, 1e-9);
  EXPECT_GT(ratios.max_abs_deviation, 0.03);
}

TEST(Quantile, InterpolatesBetweenOrderStatistics) {
  EXPECT_DOUBLE_EQ(Quantile({4, 1, 3, 2}, 0.5), 2.5);
  EXPECT_DOUBLE_EQ(Quantile({4, 1, 3}, 0.5), 3.0);
  EXPECT_DOUBLE_EQ(Quantile({4, 1, 3, 2}, 1.0), 4.0);
  EXPECT_DOUBLE_EQ(Quantile({}, 0.5), 0.0);
}

}  // namespace
}  // namespace uw
