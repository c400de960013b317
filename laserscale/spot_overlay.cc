#include "laserscale/spot_overlay.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Eigenvalues>
#include <opencv2/imgproc.hpp>

#include "common/util/error.h"

namespace uw {
namespace {

// Mahalanobis radii of the 68 % and 95 % ellipses of a 2D Gaussian,
// sqrt(-2 ln(1 - p)).
constexpr double kRadius68 = 1.5096;
constexpr double kRadius95 = 2.4477;

// The ellipse of `covariance` at Mahalanobis `radius` around `centre`
// (COLMAP pixels, scaled by `zoom` after shifting by -origin), drawn with
// sub-pixel precision.
void DrawEllipse(cv::Mat* canvas, const Eigen::Vector2d& centre,
                 const Eigen::Matrix2d& covariance, double radius,
                 const Eigen::Vector2d& origin, double zoom,
                 const cv::Scalar& colour, int thickness) {
  constexpr int kShift = 4;
  constexpr double kUnit = 1 << kShift;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(covariance);
  const Eigen::Vector2d axes =
      radius * zoom * eigen.eigenvalues().cwiseMax(0.0).cwiseSqrt();
  const Eigen::Vector2d major = eigen.eigenvectors().col(1);
  // OpenCV draws pixel (c, r) centred on (c, r): half a pixel off COLMAP.
  const Eigen::Vector2d at =
      (centre - origin) * zoom - Eigen::Vector2d::Constant(0.5);
  cv::ellipse(*canvas,
              cv::Point(static_cast<int>(std::lround(at.x() * kUnit)),
                        static_cast<int>(std::lround(at.y() * kUnit))),
              cv::Size(static_cast<int>(std::lround(axes(1) * kUnit)),
                       static_cast<int>(std::lround(axes(0) * kUnit))),
              std::atan2(major.y(), major.x()) * 180.0 / M_PI, 0.0, 360.0,
              colour, thickness, cv::LINE_AA, kShift);
}

cv::Point ToPoint(const Eigen::Vector2d& pixel, const Eigen::Vector2d& origin,
                  double zoom) {
  const Eigen::Vector2d at = (pixel - origin) * zoom;
  return {static_cast<int>(std::floor(at.x())),
          static_cast<int>(std::floor(at.y()))};
}

const cv::Scalar kColour68(80, 255, 80);
const cv::Scalar kColour95(0, 220, 255);
const cv::Scalar kColourIteration(255, 200, 120);
const cv::Scalar kColourProblem(40, 40, 255);

// How much thicker and larger marks and text are drawn on an image `cols`
// wide: 1 up to 1500 px, so that a 27 MP frame viewed whole (or shrunk
// into a report) still shows them.
int MarkScale(int cols) { return std::max(1, (cols + 750) / 1500); }

// Draws one spot's marks at `zoom` with `origin` at the canvas corner,
// lines `scale` pixels thick.
void DrawSpot(cv::Mat* canvas, const DetectedSpot& spot,
              const Eigen::Vector2d& origin, double zoom, int scale) {
  if (!spot.iterations.empty()) {
    // Half-transparent, so that the cloud does not hide the spot.
    cv::Mat dots = canvas->clone();
    for (const auto& [centre, covariance] : spot.iterations) {
      cv::circle(dots, ToPoint(centre, origin, zoom),
                 std::max(scale, static_cast<int>(zoom / 4)), kColourIteration,
                 -1, cv::LINE_AA);
    }
    cv::addWeighted(dots, 0.5, *canvas, 0.5, 0.0, *canvas);
  }
  const cv::Scalar marker = spot.stable ? kColour68 : kColourProblem;
  if (spot.stable) {
    DrawEllipse(canvas, spot.pixel, spot.covariance, kRadius68, origin, zoom,
                kColour68, scale);
    DrawEllipse(canvas, spot.pixel, spot.covariance, kRadius95, origin, zoom,
                kColour95, scale);
  }
  // A cross with a gap, visible at any zoom without hiding the spot.
  const cv::Point at = ToPoint(spot.pixel, origin, zoom);
  const int gap = std::max(6 * scale, static_cast<int>(3 * zoom));
  const int arm = gap + 8 * scale;
  for (const cv::Point& direction :
       {cv::Point(1, 0), cv::Point(-1, 0), cv::Point(0, 1), cv::Point(0, -1)}) {
    cv::line(*canvas, at + gap * direction, at + arm * direction, marker,
             scale);
  }
  const std::string label =
      spot.stable ? spot.laser : spot.laser + ": " + spot.problem;
  cv::putText(*canvas, label, at + cv::Point(arm + 2 * scale, -arm),
              cv::FONT_HERSHEY_SIMPLEX, 0.4 * scale, marker, scale,
              cv::LINE_AA);
}

}  // namespace

cv::Mat DrawSpotOverlay(const cv::Mat& image,
                        const std::vector<DetectedSpot>& spots) {
  if (image.empty()) throw ErrorAt("DrawSpotOverlay: empty image");
  cv::Mat canvas;
  if (image.type() == CV_8UC3) {
    canvas = image.clone();
  } else if (image.type() == CV_8UC1) {
    cv::cvtColor(image, canvas, cv::COLOR_GRAY2BGR);
  } else {
    throw ErrorAt("DrawSpotOverlay: expected an 8-bit image, got type ",
                  image.type());
  }
  const cv::Mat source = canvas.clone();
  const int scale = MarkScale(canvas.cols);
  std::vector<const DetectedSpot*> located;
  int undetected_line = 0;
  for (const DetectedSpot& spot : spots) {
    if (spot.detected) {
      DrawSpot(&canvas, spot, Eigen::Vector2d::Zero(), 1.0, scale);
      located.push_back(&spot);
    } else {
      cv::putText(canvas, spot.laser + ": " + spot.problem,
                  cv::Point(8 * scale, (18 + 16 * undetected_line++) * scale),
                  cv::FONT_HERSHEY_SIMPLEX, 0.45 * scale, kColourProblem, scale,
                  cv::LINE_AA);
    }
  }
  if (located.empty()) return canvas;

  // The strip of magnified crops, kCrop source pixels square each, as
  // large relative to the image at any size.
  constexpr int kCrop = 24;
  const int zoom = 8 * scale;
  const int tile_size = kCrop * zoom;
  const int per_row = std::max(1, canvas.cols / tile_size);
  const int rows = (static_cast<int>(located.size()) + per_row - 1) / per_row;
  cv::Mat out(canvas.rows + rows * tile_size, std::max(canvas.cols, tile_size),
              CV_8UC3, cv::Scalar::all(0));
  canvas.copyTo(out(cv::Rect(0, 0, canvas.cols, canvas.rows)));
  for (size_t i = 0; i < located.size(); ++i) {
    const DetectedSpot& spot = *located[i];
    const int x0 = static_cast<int>(std::floor(spot.pixel.x())) - kCrop / 2;
    const int y0 = static_cast<int>(std::floor(spot.pixel.y())) - kCrop / 2;
    const cv::Rect want(x0, y0, kCrop, kCrop);
    const cv::Rect have = want & cv::Rect(0, 0, source.cols, source.rows);
    cv::Mat crop(kCrop, kCrop, CV_8UC3, cv::Scalar::all(0));
    if (have.area() > 0) {
      source(have).copyTo(
          crop(cv::Rect(have.x - x0, have.y - y0, have.width, have.height)));
    }
    cv::Mat tile;
    cv::resize(crop, tile, cv::Size(tile_size, tile_size), 0, 0,
               cv::INTER_NEAREST);
    DrawSpot(&tile, spot, Eigen::Vector2d(x0, y0), zoom, scale);
    const int slot = static_cast<int>(i);
    tile.copyTo(out(cv::Rect((slot % per_row) * tile_size,
                             canvas.rows + (slot / per_row) * tile_size,
                             tile_size, tile_size)));
  }
  return out;
}

}  // namespace uw
