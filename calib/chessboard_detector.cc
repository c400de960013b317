#include "calib/chessboard_detector.h"

#include <algorithm>
#include <limits>
#include <vector>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "calib/grey_image.h"
#include "common/util/error.h"

namespace uw {
namespace {

constexpr int kMaxHalfWindow = 5;

// The corners re-indexed by a rotation of the grid by `quarter_turns` x 90°
// (a rotation keeps the board's handedness; a transpose would mirror it).
// Quarter turns are only possible on square grids.
std::vector<Eigen::Vector2d> Rotated(const std::vector<Eigen::Vector2d>& in,
                                     int width, int height, int quarter_turns) {
  std::vector<Eigen::Vector2d> out(in.size());
  for (int j = 0; j < height; ++j) {
    for (int i = 0; i < width; ++i) {
      int si = i;
      int sj = j;
      switch (quarter_turns) {
        case 1:
          si = j;
          sj = width - 1 - i;
          break;
        case 2:
          si = width - 1 - i;
          sj = height - 1 - j;
          break;
        case 3:
          si = height - 1 - j;
          sj = i;
          break;
        default:
          break;
      }
      out[j * width + i] = in[sj * width + si];
    }
  }
  return out;
}

// How nearly the grid's rows run left to right in the image, and its first
// corner sits top left: the mean row direction's x, normalised.
double LeftToRightScore(const std::vector<Eigen::Vector2d>& corners, int width,
                        int height) {
  Eigen::Vector2d along_rows = Eigen::Vector2d::Zero();
  for (int j = 0; j < height; ++j) {
    along_rows += corners[j * width + width - 1] - corners[j * width];
  }
  return along_rows.x() / along_rows.norm();
}

// How nearly the grid's rows run toward the image's lower right.
double TowardLowerRightScore(const std::vector<Eigen::Vector2d>& corners,
                             int width, int height) {
  Eigen::Vector2d along_rows = Eigen::Vector2d::Zero();
  for (int j = 0; j < height; ++j) {
    along_rows += corners[j * width + width - 1] - corners[j * width];
  }
  return along_rows.normalized().dot(Eigen::Vector2d(1.0, 1.0).normalized());
}

}  // namespace

BoardObservation DetectChessboard(const cv::Mat& image,
                                  const CalibrationBoard& board,
                                  const std::string& image_name) {
  if (board.kind != BoardKind::kChessboard) {
    throw ErrorAt(image_name, ": DetectChessboard needs a chessboard");
  }
  const cv::Mat grey = GreyImage(image, image_name);
  BoardObservation observation;
  observation.image = image_name;
  std::vector<cv::Point2f> found;
  const int flags = cv::CALIB_CB_NORMALIZE_IMAGE | cv::CALIB_CB_EXHAUSTIVE |
                    cv::CALIB_CB_ACCURACY;
  const cv::Size pattern(board.grid_width, board.grid_height);
  bool ok = cv::findChessboardCornersSB(grey, pattern, found, flags) &&
            static_cast<int>(found.size()) == board.NumCorners();
  if (!ok) {
    // The classic detector finds some boards the sector-based one misses
    // (one of OpenCV's own sample images).
    ok = cv::findChessboardCorners(
             grey, pattern, found,
             cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE) &&
         static_cast<int>(found.size()) == board.NumCorners();
    if (!ok) return observation;
  }
  // Both refined on the saddle by cornerSubPix, in a window that stays
  // inside the four squares around the corner (0.4 of the shortest
  // corner-to-corner distance, at most 11x11 px): on rendered boards this
  // brings the sector-based detector's 0.12 px RMS to 0.07 px.
  double shortest = std::numeric_limits<double>::infinity();
  for (int j = 0; j < board.grid_height; ++j) {
    for (int i = 0; i < board.grid_width; ++i) {
      const cv::Point2f& corner = found[j * board.grid_width + i];
      if (i + 1 < board.grid_width) {
        shortest = std::min<double>(
            shortest, cv::norm(found[j * board.grid_width + i + 1] - corner));
      }
      if (j + 1 < board.grid_height) {
        shortest = std::min<double>(
            shortest, cv::norm(found[(j + 1) * board.grid_width + i] - corner));
      }
    }
  }
  const int half_window =
      std::clamp(static_cast<int>(0.4 * shortest), 1, kMaxHalfWindow);
  cv::cornerSubPix(
      grey, found, cv::Size(half_window, half_window), cv::Size(-1, -1),
      cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50,
                       1e-3));
  std::vector<Eigen::Vector2d> corners;
  corners.reserve(found.size());
  for (const cv::Point2f& corner : found)
    corners.emplace_back(corner.x, corner.y);

  const int w = board.grid_width;
  const int h = board.grid_height;
  // A square grid: the quarter turn whose rows run most nearly left to
  // right (mrgingham's order). Otherwise only a half turn is possible: the
  // one whose rows run toward the lower right, so that views from nearby
  // (a stereo pair) number the same physical corners alike even when the
  // board is held upright.
  const std::vector<int> turns =
      w == h ? std::vector<int>{0, 1, 2, 3} : std::vector<int>{0, 2};
  double best_score = -2.0;
  for (const int turn : turns) {
    std::vector<Eigen::Vector2d> candidate = Rotated(corners, w, h, turn);
    const double score = w == h ? LeftToRightScore(candidate, w, h)
                                : TowardLowerRightScore(candidate, w, h);
    if (score > best_score) {
      best_score = score;
      observation.pixels = std::move(candidate);
    }
  }
  observation.weights.assign(observation.pixels.size(), 1.0);
  return observation;
}

}  // namespace uw
