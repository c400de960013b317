#include "calib/charuco_detector.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include <opencv2/aruco.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "calib/grey_image.h"
#include "common/util/error.h"

namespace uw {
namespace {

int NumSquaresX(const CalibrationBoard& board) { return board.grid_width + 1; }
int NumSquaresY(const CalibrationBoard& board) { return board.grid_height + 1; }

// Whether square (x, y) (y from the top) holds a marker.
bool HasMarker(const CalibrationBoard& board, int x, int y) {
  if (board.legacy) return (NumSquaresY(board) - 1 - y) % 2 != x % 2;
  return y % 2 != x % 2;
}

}  // namespace

void CharucoOptions::Check() const {
  if (min_corners < 4) {
    throw Error("ChArUco options: min_corners must be >= 4");
  }
}

cv::Point CharucoMarkerSquare(const CalibrationBoard& board, int id) {
  int count = 0;
  for (int y = 0; y < NumSquaresY(board); ++y) {
    for (int x = 0; x < NumSquaresX(board); ++x) {
      if (!HasMarker(board, x, y)) continue;
      if (count++ == id) return {x, y};
    }
  }
  return {-1, -1};
}

BoardObservation DetectCharuco(const cv::Mat& image,
                               const CalibrationBoard& board,
                               const std::string& image_name,
                               const CharucoOptions& options,
                               int* num_markers) {
  options.Check();
  if (board.kind != BoardKind::kCharuco) {
    throw ErrorAt(image_name, ": DetectCharuco needs a charuco board");
  }
  const auto& dictionaries = ArucoDictionaries();
  const auto entry =
      std::find_if(dictionaries.begin(), dictionaries.end(),
                   [&](const auto& d) { return d.first == board.dictionary; });
  if (entry == dictionaries.end()) {
    throw ErrorAt(image_name, ": unknown dictionary ", board.dictionary);
  }
  const cv::Mat grey = GreyImage(image, image_name);
  const cv::Ptr<cv::aruco::Dictionary> dictionary =
      cv::aruco::getPredefinedDictionary(
          static_cast<int>(entry - dictionaries.begin()));
  std::vector<std::vector<cv::Point2f>> marker_corners;
  std::vector<int> ids;
  // OpenCV drops the smaller of two candidate quads closer than 5 % of a
  // perimeter: on a ChArUco board that is often the marker, inside the
  // white square around it (52 instead of 34 markers in a sharp view of
  // the pyCamSet board). Without the filter a marker's border can come out
  // twice; the copies are merged below.
  const cv::Ptr<cv::aruco::DetectorParameters> parameters =
      cv::aruco::DetectorParameters::create();
  parameters->minMarkerDistanceRate = 0.0;
  cv::aruco::detectMarkers(grey, dictionary, marker_corners, ids, parameters);

  // Found markers by square: their corners on the board (x right, y down
  // from the top-left outer corner; TL, TR, BR, BL as ArUco orders them)
  // and in the image.
  struct Marker {
    std::vector<cv::Point2f> in_board;
    std::vector<cv::Point2f> in_image;
  };
  std::map<std::pair<int, int>, Marker> markers;
  std::map<std::pair<int, int>, double> perimeter;
  std::set<std::pair<int, int>> ambiguous;
  const double s = board.spacing_m;
  const double margin = 0.5 * (board.spacing_m - board.marker_m);
  for (size_t k = 0; k < ids.size(); ++k) {
    const cv::Point square = CharucoMarkerSquare(board, ids[k]);
    if (square.x < 0) continue;  // another board's, or a misread
    const float x0 = static_cast<float>(square.x * s + margin);
    const float y0 = static_cast<float>(square.y * s + margin);
    const float m = static_cast<float>(board.marker_m);
    Marker marker;
    marker.in_board = {{x0, y0}, {x0 + m, y0}, {x0 + m, y0 + m}, {x0, y0 + m}};
    marker.in_image = marker_corners[k];
    // An id seen twice: the outer of two outlines of one border (the
    // marker's corners), or, far apart, a misread: then neither.
    const std::pair<int, int> key(square.x, square.y);
    const double length = cv::arcLength(marker.in_image, true);
    const auto seen = markers.find(key);
    if (seen == markers.end()) {
      markers.emplace(key, marker);
      perimeter[key] = length;
      continue;
    }
    const cv::Point2f offset =
        (marker.in_image[0] + marker.in_image[2] - seen->second.in_image[0] -
         seen->second.in_image[2]) *
        0.5f;
    if (cv::norm(offset) > 0.25 * std::max(length, perimeter[key])) {
      ambiguous.insert(key);
    } else if (length > perimeter[key]) {
      seen->second = marker;
      perimeter[key] = length;
    }
  }
  for (const auto& key : ambiguous) markers.erase(key);
  if (num_markers != nullptr) *num_markers = static_cast<int>(markers.size());

  BoardObservation observation;
  observation.image = image_name;
  observation.pixels.assign(board.NumCorners(), Eigen::Vector2d::Zero());
  observation.weights.assign(board.NumCorners(), -1.0);
  int found = 0;
  int misplaced = 0;
  for (int j = 0; j < board.grid_height; ++j) {
    for (int i = 0; i < board.grid_width; ++i) {
      // Inner corner (i, j) is the top-left corner of square (i+1, j+1);
      // of the four squares around it, two hold markers.
      bool beside_a_marker = false;
      std::vector<cv::Point2f> in_board;
      std::vector<cv::Point2f> in_image;
      for (int y = j - 1; y <= j + 2; ++y) {
        for (int x = i - 1; x <= i + 2; ++x) {
          const auto it = markers.find({x, y});
          if (it == markers.end()) continue;
          beside_a_marker =
              beside_a_marker || (x >= i && x <= i + 1 && y >= j && y <= j + 1);
          in_board.insert(in_board.end(), it->second.in_board.begin(),
                          it->second.in_board.end());
          in_image.insert(in_image.end(), it->second.in_image.begin(),
                          it->second.in_image.end());
        }
      }
      if (!beside_a_marker) continue;
      const cv::Mat homography = cv::findHomography(in_board, in_image, 0);
      if (homography.empty()) continue;
      std::vector<cv::Point2f> fitted;
      cv::perspectiveTransform(in_board, fitted, homography);
      double squares = 0.0;
      for (size_t q = 0; q < fitted.size(); ++q) {
        squares += std::pow(cv::norm(fitted[q] - in_image[q]), 2);
      }
      const double fit_rms = std::sqrt(squares / fitted.size());
      const double marker_px = cv::norm(in_image[1] - in_image[0]);
      // Markers that do not fit one homography (by a quarter of a marker's
      // side; a tenth of that is usual) are not where the layout says: the
      // corner is not trusted.
      if (fit_rms > 0.25 * marker_px) {
        ++misplaced;
        continue;
      }
      const cv::Point2f corner(static_cast<float>((i + 1) * s),
                               static_cast<float>((j + 1) * s));
      std::vector<cv::Point2f> predicted;
      cv::perspectiveTransform(
          std::vector<cv::Point2f>{
              corner, corner + cv::Point2f(static_cast<float>(margin), 0.0f),
              corner + cv::Point2f(0.0f, static_cast<float>(margin))},
          predicted, homography);
      // The white margin around a marker, in pixels: the window stays in it.
      const double margin_px = std::min(cv::norm(predicted[1] - predicted[0]),
                                        cv::norm(predicted[2] - predicted[0]));
      const int half_window = std::max(2, static_cast<int>(0.8 * margin_px));
      const cv::Point2f p = predicted[0];
      if (p.x < half_window + 1 || p.y < half_window + 1 ||
          p.x > grey.cols - half_window - 2 ||
          p.y > grey.rows - half_window - 2) {
        continue;
      }
      std::vector<cv::Point2f> refined = {p};
      cv::cornerSubPix(
          grey, refined, cv::Size(half_window, half_window), cv::Size(-1, -1),
          cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 40,
                           1e-3));
      if (cv::norm(refined[0] - p) > 0.5 * half_window) continue;
      const int index = j * board.grid_width + i;
      observation.pixels[index] = Eigen::Vector2d(refined[0].x, refined[0].y);
      observation.weights[index] = 1.0;
      ++found;
    }
  }
  // A board of the other layout puts every other row of markers one square
  // off: the local fits fail around most corners.
  if (misplaced > found) {
    throw ErrorAt(
        image_name, ": the markers do not sit where ", board.ToString(),
        " puts them (", misplaced, " of ", misplaced + found,
        " corners' markers disagree); is the board of the ",
        board.legacy ? "new (drop ':legacy')" : "legacy (add ':legacy')",
        " layout?");
  }
  if (found < options.min_corners) {
    observation.pixels.clear();
    observation.weights.clear();
  }
  return observation;
}

}  // namespace uw
