#include "report/survey_map.h"

#include <gtest/gtest.h>

#include "common/mesh/test_meshes.h"
#include "common/util/error.h"

namespace uw {
namespace {

// The map from data in memory, as the survey report draws it: model camera
// centres, the navigation and no true track.
TEST(SurveyMap, DrawsCamerasAndNavigationWithoutATrueTrack) {
  SurveyMapData data;
  AddGrid(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(10, 0, 1),
          Eigen::Vector3d(0, 6, 0), 10, 6, &data.mesh);
  const std::vector<Eigen::Vector3d> centres = {
      {2, 3, 2}, {5, 3, 2}, {8, 3, 2}};
  for (size_t i = 0; i < centres.size(); ++i) {
    const std::string name = std::to_string(i) + ".png";
    data.cameras.push_back({name, 1, centres[i]});
    data.navigation.push_back({name, 1, centres[i] + Eigen::Vector3d(0, 1, 0)});
  }
  data.cameras_label = "model camera centres";
  data.navigation_label = "navigation (nav.csv)";
  SurveyMapOptions options;
  options.width_px = 800;
  const SurveyMap map = DrawSurveyMap(data, options);
  ASSERT_EQ(map.image.cols, 800);
  for (const Eigen::Vector3d& centre : centres) {
    const Eigen::Vector2d pixel = map.PixelFromWorld(centre.head<2>());
    EXPECT_EQ(map.image.at<cv::Vec3b>(static_cast<int>(std::lround(pixel.y())),
                                      static_cast<int>(std::lround(pixel.x()))),
              DiveColor(1));
  }
  const Eigen::Vector2d nav = map.PixelFromWorld(Eigen::Vector2d(3.5, 4));
  EXPECT_EQ(map.image.at<cv::Vec3b>(static_cast<int>(std::lround(nav.y())),
                                    static_cast<int>(std::lround(nav.x()))),
            NavigationTrackColor());
  // No true track: nothing black inside the map but its frame.
  const cv::Rect inside(map.map_area.x + 3, map.map_area.y + 3,
                        map.map_area.width - 6, map.map_area.height - 6);
  const cv::Mat black = map.image(inside) == cv::Scalar(0, 0, 0);
  cv::Mat all_black;
  cv::Mat channels[3];
  cv::split(black, channels);
  cv::bitwise_and(channels[0], channels[1], all_black);
  cv::bitwise_and(all_black, channels[2], all_black);
  // Camera dots have dark rims; a track would add far more.
  EXPECT_LT(cv::countNonZero(all_black), 600);
}

TEST(SurveyMap, RefusesAnEmptyMeshOrNoCameras) {
  SurveyMapData data;
  data.cameras.push_back({"a.png", 1, Eigen::Vector3d::Zero()});
  EXPECT_THROW(DrawSurveyMap(data, SurveyMapOptions()), Error);
  AddGrid(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0),
          Eigen::Vector3d(0, 1, 0), 1, 1, &data.mesh);
  data.cameras.clear();
  EXPECT_THROW(DrawSurveyMap(data, SurveyMapOptions()), Error);
  SurveyMapOptions small;
  small.width_px = 100;
  EXPECT_THROW(small.Check(), Error);
}

}  // namespace
}  // namespace uw
