// uwsim map: a top view of a survey for the docs and the survey report. The
// world's mesh seen from above as a hillshaded, colour-ramped height map;
// the true camera centres coloured by dive; the true vehicle track and the
// navigation track; axes in metres (x east, y north), a scale bar, a north
// arrow, a height colour bar and a legend below the map, never over it.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "colmap_plugins/mesh/mesh.h"

namespace uw::sim {

struct SurveyMapOptions {
  // Width of the whole figure; the map keeps the world's aspect ratio and
  // the height follows (a map at most 1.5 × width tall).
  int width_px = 1600;
  // Drawn above the map when not empty (ASCII: the figure's font has no
  // other glyphs).
  std::string title;

  void Check() const;  // width_px in [800, 8000]
};

// A camera centre or a navigation record: world frame (ENU), metres.
struct SurveyMapPoint {
  std::string image_name;
  int dive = 1;
  Eigen::Vector3d position_in_world = Eigen::Vector3d::Zero();
};

// What the map shows, as read from an uwsim output folder.
struct SurveyMapData {
  TriangleMesh mesh;                       // truth/mesh.ply
  std::vector<SurveyMapPoint> cameras;     // truth/images.txt centres; dive
                                           // from truth/nav.csv
  std::vector<SurveyMapPoint> true_track;  // truth/nav.csv, file order
  std::vector<SurveyMapPoint> navigation;  // nav.csv, file order
};

// Reads truth/mesh.ply, truth/images.txt (COLMAP text), truth/nav.csv and
// nav.csv under `sim_dir`. Throws uw::Error naming a missing file, a
// malformed nav.csv row (file:line), or an image of truth/images.txt with no
// row in truth/nav.csv.
SurveyMapData ReadSurveyMapData(const std::filesystem::path& sim_dir);

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

// Reads `sim_dir`, draws the map and writes it to `out` atomically, as PNG
// or JPEG by the extension (.png, .jpg, .jpeg).
void WriteSurveyMap(const std::filesystem::path& sim_dir,
                    const std::filesystem::path& out,
                    const SurveyMapOptions& options);

}  // namespace uw::sim
