// A top view of a survey, for the survey report and `uwsim map`: a mesh
// seen from above as a hillshaded, colour-ramped height map; camera centres
// coloured by dive; a reference vehicle track and the navigation track;
// axes in metres (x east, y north), a scale bar, a north arrow, a height
// colour bar and a legend below the map, never over it. All positions in
// one world frame: east-north-up metres, or (MapFrame::kModelUnits) a
// model's own frame, turned so that z is up, and labelled as what it is.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "common/mesh/mesh.h"

namespace uw {

enum class MapFrame {
  // A navigation-fused or uwsim model: "x east (m)", "y north (m)",
  // "height z (m, up)", a north arrow and a scale in metres.
  kEastNorthUpMetres,
  // A model in its own frame and units (stock COLMAP): "x (model units)",
  // "y (model units)", "height (model units, up)", a scale in model units
  // and no north arrow. Its z must have been turned up (UpFromCameras).
  kModelUnits,
};

struct SurveyMapOptions {
  // Width of the whole figure; the map keeps the world's aspect ratio and
  // the height follows (a map at most 1.5 × width tall).
  int width_px = 1600;
  // Drawn above the map when not empty (ASCII: the figure's font has no
  // other glyphs).
  std::string title;
  MapFrame frame = MapFrame::kEastNorthUpMetres;

  void Check() const;  // width_px in [800, 8000]
};

// A camera centre or a navigation record: world frame (ENU), metres.
struct SurveyMapPoint {
  std::string image_name;
  int dive = 1;
  Eigen::Vector3d position_in_world = Eigen::Vector3d::Zero();
};

// What the map shows. Either track may be empty (then it has no legend
// row); the horizontal navigation error is printed when both share image
// names. Labels are ASCII.
struct SurveyMapData {
  TriangleMesh mesh;
  std::vector<SurveyMapPoint> cameras;     // dots, coloured by dive
  std::vector<SurveyMapPoint> true_track;  // black line, file order
  std::vector<SurveyMapPoint> navigation;  // magenta line + dots, file order
  std::string cameras_label = "camera centres";
  std::string true_track_label = "true vehicle track";
  std::string navigation_label = "navigation";
};

// The figure and where world points land on it.
struct SurveyMap {
  cv::Mat image;      // CV_8UC3, BGR
  cv::Rect map_area;  // the framed map; legend and labels lie outside it
  double pixels_per_metre = 0.0;
  Eigen::Vector2d top_left_in_world = Eigen::Vector2d::Zero();  // x min, y max

  // Continuous pixel coordinates (column, row) of a world point, with pixel
  // centres at integers as OpenCV draws.
  Eigen::Vector2d PixelFromWorld(const Eigen::Vector2d& xy_in_world) const;
};

// Throws uw::Error on an empty mesh or no cameras.
SurveyMap DrawSurveyMap(const SurveyMapData& data,
                        const SurveyMapOptions& options);

// Colours of the overlays (BGR), for tests and for figures that match.
cv::Vec3b DiveColor(int dive);  // dive >= 1; cycles after 7 dives
cv::Vec3b TrueTrackColor();
cv::Vec3b NavigationTrackColor();

}  // namespace uw
