#include "laserscale/beam_image.h"

#include <gtest/gtest.h>

#include "laserscale/spot_detector_testing.h"

namespace uw {
namespace {

TEST(BeamImage, ProjectsTheBeamBetweenTheRanges) {
  const std::vector<Eigen::Vector2d> beam =
      lsd::BeamImage(PinholeCamera(320, 240, 400.0), OneLaser().lasers[0],
                     SpotDetectorOptions());
  ASSERT_EQ(beam.size(), 65u);
  EXPECT_LT((beam.front() - Eigen::Vector2d(200.0, 120.0)).norm(), 1e-9);
  EXPECT_LT((beam.back() - Eigen::Vector2d(160.0 + 40.0 / 6.0, 120.0)).norm(),
            1e-9);
}

TEST(DistanceToPolyline, IsToTheNearestSegment) {
  const std::vector<Eigen::Vector2d> line = {
      {0.0, 0.0}, {10.0, 0.0}, {10.0, 10.0}};
  EXPECT_DOUBLE_EQ(lsd::DistanceToPolyline({5.0, 3.0}, line), 3.0);
  EXPECT_DOUBLE_EQ(lsd::DistanceToPolyline({12.0, 5.0}, line), 2.0);
  EXPECT_DOUBLE_EQ(lsd::DistanceToPolyline({-3.0, 4.0}, line), 5.0);
  EXPECT_DOUBLE_EQ(lsd::DistanceToPolyline({4.0, 5.0}, {{1.0, 1.0}}), 5.0);
  EXPECT_EQ(lsd::DirectionNear(line, {12.0, 5.0}), Eigen::Vector2d(0.0, 1.0));
  EXPECT_EQ(lsd::DirectionNear(line, {5.0, -1.0}), Eigen::Vector2d(1.0, 0.0));
}

// Where two beams pass within the margin, a point belongs to the nearer.
TEST(OnOwnBeam, RefusesPointsNearerAnotherBeam) {
  const std::vector<std::vector<Eigen::Vector2d>> beams = {
      {{0.0, 0.0}, {100.0, 0.0}}, {{0.0, 10.0}, {100.0, 10.0}}, {}};
  EXPECT_TRUE(lsd::OnOwnBeam({50.0, 3.0}, beams, 0, 8.0));
  EXPECT_FALSE(lsd::OnOwnBeam({50.0, 3.0}, beams, 1, 8.0));
  EXPECT_FALSE(lsd::OnOwnBeam({50.0, 6.0}, beams, 0, 8.0));
  EXPECT_TRUE(lsd::OnOwnBeam({50.0, 6.0}, beams, 1, 8.0));
  EXPECT_FALSE(lsd::OnOwnBeam({50.0, -9.0}, beams, 0, 8.0));
}

}  // namespace
}  // namespace uw
