#include "colmap_plugins/ba/track_line.h"

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "colmap_plugins/align/track_metrics.h"

namespace uw {
namespace {

// `lines` parallel lines of 21 camera centres along x, `line_spacing_m`
// apart in y, each `wiggle_m` off its line (alternating across and up).
std::vector<Eigen::Vector3d> Track(int lines, double line_spacing_m,
                                   double wiggle_m) {
  std::vector<Eigen::Vector3d> centres;
  for (int line = 0; line < lines; ++line) {
    for (int i = 0; i < 21; ++i) {
      const double sign = i % 2 == 0 ? 1.0 : -1.0;
      centres.emplace_back(0.57 * i, line * line_spacing_m + sign * wiggle_m,
                           sign * wiggle_m);
    }
  }
  return centres;
}

// A model with cameras at `centres` and, for each, a prior 1 m off it
// (navigation noise must not hide the line).
struct TrackModel {
  Reconstruction model;
  std::vector<ImagePosePrior> priors;
};
TrackModel ModelOf(const std::vector<Eigen::Vector3d>& centres) {
  TrackModel track;
  for (size_t i = 0; i < centres.size(); ++i) {
    Image image;
    image.image_id = static_cast<image_t>(i + 1);
    image.camera_id = 1;
    image.name = std::to_string(i) + ".png";
    image.cam_from_world.translation = -centres[i];
    track.model.AddImage(image);
    ImagePosePrior prior;
    prior.image_id = image.image_id;
    prior.position_in_world =
        centres[i] + Eigen::Vector3d(i % 2 ? 1.0 : -1.0, i % 3 ? 1.0 : -1.0, 0);
    track.priors.push_back(prior);
  }
  return track;
}

TEST(TrackLine, TrackAxisMeasuresTheSpreadAlongAndAcross) {
  const TrackAxis track = TrackAxisFromCentres(Track(2, 2.0, 0.0));
  // 0 .. 11.4 m uniformly: sqrt((21^2 - 1) / 12) x 0.57 m.
  EXPECT_NEAR(track.rms_along, 0.57 * std::sqrt((21.0 * 21.0 - 1.0) / 12.0),
              1e-9);
  EXPECT_NEAR(track.rms_across, 1.0, 1e-9);
  EXPECT_NEAR(track.direction.x(), 1.0, 1e-12);
}

TEST(TrackLine, WarnsForASinglePassWithoutAttitude) {
  const TrackModel pass = ModelOf(Track(1, 0.0, 0.06));
  const auto warning = TrackLineWarning(pass.model, pass.priors, false);
  ASSERT_TRUE(warning);
  EXPECT_NE(warning->find("21 camera centres"), std::string::npos) << *warning;
  EXPECT_NE(warning->find("nearly on one line"), std::string::npos);
  // Priors without rotation: a log without attitude, nothing to fuse.
  EXPECT_NE(warning->find("The log has no attitude to fix it with"),
            std::string::npos);
  TrackModel with_attitude = pass;
  with_attitude.priors[3].cam_from_world_rotation =
      Eigen::Quaterniond::Identity();
  EXPECT_NE(TrackLineWarning(with_attitude.model, with_attitude.priors, false)
                ->find("Fuse the log's roll and pitch too (--Nav.strategy "
                       "prior --Nav.use_attitude 1)"),
            std::string::npos);
  // Attitude priors hold the rotation; a lawnmower's lines hold it too.
  EXPECT_FALSE(TrackLineWarning(pass.model, pass.priors, true));
  const TrackModel lawnmower = ModelOf(Track(3, 1.0, 0.06));
  EXPECT_FALSE(TrackLineWarning(lawnmower.model, lawnmower.priors, false));
  EXPECT_FALSE(TrackLineWarning(pass.model, {}, false));
}

TEST(TrackLine, WarnsWhenThePriorsRotationIsWeak) {
  const auto warning = WeakRotationWarning(8.9, false);
  ASSERT_TRUE(warning);
  EXPECT_NE(warning->find("only to 8.9 deg"), std::string::npos) << *warning;
  EXPECT_FALSE(WeakRotationWarning(8.9, true));
  EXPECT_FALSE(WeakRotationWarning(4.3, false));
}

}  // namespace
}  // namespace uw
