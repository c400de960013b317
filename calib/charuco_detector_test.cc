#include "calib/charuco_detector.h"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include <gtest/gtest.h>
#include <opencv2/aruco/charuco.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "common/util/error.h"
#include "common/util/random.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

constexpr int kSquarePx = 60;  // texture pixels per square

// The board as printed (white margin of one square), kSquarePx a square:
// black squares where no marker sits, markers drawn by OpenCV's ArUco.
cv::Mat BoardTexture(const CalibrationBoard& board) {
  const int sx = board.grid_width + 1;
  const int sy = board.grid_height + 1;
  cv::Mat texture(kSquarePx * (sy + 2), kSquarePx * (sx + 2), CV_8UC1,
                  cv::Scalar(255));
  const cv::Ptr<cv::aruco::Dictionary> dictionary =
      cv::aruco::getPredefinedDictionary(cv::aruco::DICT_4X4_1000);
  const int marker_px = static_cast<int>(
      std::lround(kSquarePx * board.marker_m / board.spacing_m));
  const int margin_px = (kSquarePx - marker_px) / 2;
  for (int y = 0; y < sy; ++y) {
    for (int x = 0; x < sx; ++x) {
      const cv::Rect square((x + 1) * kSquarePx, (y + 1) * kSquarePx, kSquarePx,
                            kSquarePx);
      texture(square).setTo(cv::Scalar(0));
    }
  }
  for (int id = 0;; ++id) {
    const cv::Point square = CharucoMarkerSquare(board, id);
    if (square.x < 0) break;
    const cv::Rect cell((square.x + 1) * kSquarePx, (square.y + 1) * kSquarePx,
                        kSquarePx, kSquarePx);
    texture(cell).setTo(cv::Scalar(255));
    cv::Mat marker;
    cv::aruco::drawMarker(dictionary, id, marker_px, marker, 1);
    marker.copyTo(texture(cv::Rect(cell.x + margin_px, cell.y + margin_px,
                                   marker_px, marker_px)));
  }
  return texture;
}

struct View {
  cv::Mat image;
  std::vector<Eigen::Vector2d> corners;  // truth, mrcal's order
  std::vector<bool> inside;              // 4 px inside the image
};

// The board seen through a homography: rotated, tilted, with blur and noise.
View RenderView(const cv::Mat& texture, const CalibrationBoard& board,
                double angle_deg, double tilt, uint64_t seed) {
  const cv::Size size(1280, 1024);
  const double scale = 0.75;  // image pixels per texture pixel
  const double a = angle_deg * M_PI / 180.0;
  cv::Mat homography =
      (cv::Mat_<double>(3, 3) << scale * std::cos(a), -scale * std::sin(a), 0,
       scale * std::sin(a), scale * std::cos(a), 0, tilt, 0.3 * tilt, 1);
  // Centre the board in the image.
  std::vector<cv::Point2f> centre;
  cv::perspectiveTransform(
      std::vector<cv::Point2f>{
          cv::Point2f(texture.cols / 2.0f - 0.5f, texture.rows / 2.0f - 0.5f)},
      centre, homography);
  const cv::Mat shift =
      (cv::Mat_<double>(3, 3) << 1, 0, size.width / 2.0 - 0.5 - centre[0].x, 0,
       1, size.height / 2.0 - 0.5 - centre[0].y, 0, 0, 1);
  homography = shift * homography;
  View view;
  // Rendered at 4 x 4 samples a pixel and averaged (a 4x4 block centred
  // on pixel x is the fine pixels 4 x .. 4 x + 3, centre 4 x + 1.5): one
  // sample a pixel would alias the edges by a tenth of a pixel or more.
  const cv::Mat fine_from_image =
      (cv::Mat_<double>(3, 3) << 4, 0, 1.5, 0, 4, 1.5, 0, 0, 1);
  cv::Mat fine;
  cv::warpPerspective(texture, fine, fine_from_image * homography,
                      cv::Size(4 * size.width, 4 * size.height),
                      cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(128));
  cv::Mat warped;
  cv::resize(fine, warped, size, 0, 0, cv::INTER_AREA);
  cv::GaussianBlur(warped, warped, cv::Size(0, 0), 0.8);
  cv::Mat noisy(size, CV_8UC1);
  SplitMix64Stream random(seed);
  for (int r = 0; r < size.height; ++r) {
    for (int c = 0; c < size.width; ++c) {
      const double level = 30.0 + 190.0 * warped.at<uint8_t>(r, c) / 255.0 +
                           3.0 * random.Gaussian();
      noisy.at<uint8_t>(r, c) = cv::saturate_cast<uint8_t>(level);
    }
  }
  view.image = noisy;
  for (int j = 0; j < board.grid_height; ++j) {
    for (int i = 0; i < board.grid_width; ++i) {
      // Texture pixel centres are whole numbers: square edges at k - 0.5.
      const cv::Point2f corner((i + 2) * kSquarePx - 0.5f,
                               (j + 2) * kSquarePx - 0.5f);
      std::vector<cv::Point2f> pixel;
      cv::perspectiveTransform(std::vector<cv::Point2f>{corner}, pixel,
                               homography);
      view.corners.emplace_back(pixel[0].x, pixel[0].y);
      view.inside.push_back(pixel[0].x > 4 && pixel[0].y > 4 &&
                            pixel[0].x < size.width - 5 &&
                            pixel[0].y < size.height - 5);
    }
  }
  return view;
}

struct Accuracy {
  int inside = 0;
  int found = 0;
  double rms_px = 0.0;
  double max_px = 0.0;
  Eigen::Vector2d bias = Eigen::Vector2d::Zero();
};

Accuracy Compare(const View& view, const BoardObservation& observation) {
  Accuracy accuracy;
  double sum = 0.0;
  for (size_t k = 0; k < view.corners.size(); ++k) {
    accuracy.inside += view.inside[k];
    if (!observation.Found() || observation.weights[k] <= 0.0) continue;
    const double error = (observation.pixels[k] - view.corners[k]).norm();
    accuracy.bias += observation.pixels[k] - view.corners[k];
    ++accuracy.found;
    sum += error * error;
    accuracy.max_px = std::max(accuracy.max_px, error);
  }
  if (accuracy.found > 0) accuracy.bias /= accuracy.found;
  accuracy.rms_px = accuracy.found > 0 ? std::sqrt(sum / accuracy.found) : 0;
  return accuracy;
}

// Both layouts (noise 3 levels, blur 0.8 px): every corner in view found,
// to under a tenth of a pixel RMS and no offset; OpenCV 4.6's own
// interpolation, on the layout it knows, for comparison (its corners come
// out half a pixel off in x and y here: another pixel convention).
TEST(DetectCharuco, FindsTheCornersOfRenderedBoards) {
  for (const bool legacy : {false, true}) {
    const CalibrationBoard board =
        ParseBoard(std::string("charuco:20x20:0.004:0.0032:DICT_4X4_1000") +
                   (legacy ? ":legacy" : ""));
    const cv::Mat texture = BoardTexture(board);
    for (const double angle : {0.0, 17.0, -35.0}) {
      const View view = RenderView(texture, board, angle, 1.5e-4, 3);
      int markers = 0;
      const BoardObservation observation =
          DetectCharuco(view.image, board, "view", CharucoOptions(), &markers);
      const Accuracy ours = Compare(view, observation);
      std::string opencv = "n/a (legacy layout)";
      if (!legacy) {
        const cv::Ptr<cv::aruco::CharucoBoard> reference =
            cv::aruco::CharucoBoard::create(
                20, 20, 0.004f, 0.0032f,
                cv::aruco::getPredefinedDictionary(cv::aruco::DICT_4X4_1000));
        std::vector<std::vector<cv::Point2f>> marker_corners;
        std::vector<int> ids;
        cv::aruco::detectMarkers(view.image, reference->dictionary,
                                 marker_corners, ids);
        std::vector<cv::Point2f> corners;
        std::vector<int> corner_ids;
        cv::aruco::interpolateCornersCharuco(marker_corners, ids, view.image,
                                             reference, corners, corner_ids);
        BoardObservation theirs;
        theirs.image = "view";
        theirs.pixels.assign(board.NumCorners(), Eigen::Vector2d::Zero());
        theirs.weights.assign(board.NumCorners(), -1.0);
        for (size_t k = 0; k < corner_ids.size(); ++k) {
          theirs.pixels[corner_ids[k]] =
              Eigen::Vector2d(corners[k].x, corners[k].y);
          theirs.weights[corner_ids[k]] = 1.0;
        }
        const Accuracy accuracy = Compare(view, theirs);
        char text[160];
        std::snprintf(text, sizeof(text),
                      "%d corners, RMS %.3f px (mean offset %+.3f, %+.3f), "
                      "max %.3f px",
                      accuracy.found, accuracy.rms_px, accuracy.bias.x(),
                      accuracy.bias.y(), accuracy.max_px);
        opencv = text;
      }
      std::printf(
          "[ figures ] %s layout, %+.0f deg: %d markers; ours %d of %d "
          "corners in view, RMS %.3f px (mean offset %+.3f, %+.3f), max "
          "%.3f px; OpenCV interpolateCornersCharuco %s\n",
          legacy ? "legacy" : "4.6", angle, markers, ours.found, ours.inside,
          ours.rms_px, ours.bias.x(), ours.bias.y(), ours.max_px,
          opencv.c_str());
      EXPECT_GE(ours.found, 0.95 * ours.inside) << angle;
      EXPECT_LT(ours.rms_px, 0.15) << angle;
      EXPECT_LT(ours.max_px, 0.4) << angle;
      EXPECT_LT(ours.bias.norm(), 0.02) << angle;
    }
  }
}

// The pyCamSet images (20x20 squares, 4 mm, DICT_4X4_1000): their markers
// sit as OpenCV 4.6 lays a board out. Counted on three sharp views.
TEST(DetectCharuco, FindsTheBoardInRealImages) {
  const fs::path dir = fs::path(UW_REALDATA_DIR) / "charuco_pycamset_3cam";
  ASSERT_TRUE(fs::is_directory(dir))
      << dir << " is missing: the tests read ../shared/realdata";
  const CalibrationBoard board =
      ParseBoard("charuco:20x20:0.004:0.0032:DICT_4X4_1000");
  for (const char* name : {"1/cal1.jpg", "2/cal8.jpg", "3/cal1.jpg"}) {
    const cv::Mat image =
        cv::imread((dir / name).string(), cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(image.empty()) << name;
    int markers = 0;
    const BoardObservation observation =
        DetectCharuco(image, board, name, CharucoOptions(), &markers);
    std::printf("[ figures ] %s: %d markers, %d corners\n", name, markers,
                observation.NumFoundCorners());
    EXPECT_GE(markers, 45) << name;
    EXPECT_GE(observation.NumFoundCorners(), 100) << name;
  }
}

TEST(DetectCharuco, NoBoardAndBadInput) {
  const CalibrationBoard board =
      ParseBoard("charuco:20x20:0.004:0.0032:DICT_4X4_1000");
  const cv::Mat flat(480, 640, CV_8UC1, cv::Scalar(128));
  EXPECT_FALSE(DetectCharuco(flat, board, "flat", CharucoOptions()).Found());
  EXPECT_THROW(DetectCharuco(flat, ParseBoard("chessboard:9x6:0.02"), "x",
                             CharucoOptions()),
               Error);
  EXPECT_THROW(DetectCharuco(cv::Mat(), board, "x", CharucoOptions()), Error);
}

// The other layout's board is refused, not misread (its corners would be
// a square off, every other row).
TEST(DetectCharuco, RefusesABoardOfTheOtherLayout) {
  const CalibrationBoard legacy =
      ParseBoard("charuco:20x20:0.004:0.0032:DICT_4X4_1000:legacy");
  const CalibrationBoard modern =
      ParseBoard("charuco:20x20:0.004:0.0032:DICT_4X4_1000");
  for (const bool printed_legacy : {false, true}) {
    const View view = RenderView(BoardTexture(printed_legacy ? legacy : modern),
                                 legacy, 17.0, 1.5e-4, 3);
    try {
      DetectCharuco(view.image, printed_legacy ? modern : legacy, "view.png",
                    CharucoOptions());
      ADD_FAILURE() << "read a board of the other layout";
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what())
                    .find("view.png: the markers do not "
                          "sit where"),
                std::string::npos)
          << error.what();
      EXPECT_NE(std::string(error.what())
                    .find(printed_legacy ? "add ':legacy'" : "drop ':legacy'"),
                std::string::npos)
          << error.what();
    }
  }
}

}  // namespace
}  // namespace uw
