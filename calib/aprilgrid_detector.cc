#include "calib/aprilgrid_detector.h"

#include <array>
#include <map>

#include <Eigen/LU>
#include <opencv2/imgproc.hpp>

#include "calib/apriltag_detector.h"
#include "colmap_plugins/util/error.h"

namespace uw {
namespace {

// The 3x3 maximum shrinks the black border by one pixel on every side:
// each corner moves back out by one pixel across both of its edges.
void UndoDilation(AprilTagDetection* tag) {
  const auto& p = tag->corners;
  std::array<Eigen::Vector2d, 4> moved;
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector2d& corner = p[k];
    const Eigen::Vector2d centre = 0.25 * (p[0] + p[1] + p[2] + p[3]);
    Eigen::Matrix2d normals;
    int row = 0;
    for (const Eigen::Vector2d& other : {p[(k + 1) % 4], p[(k + 3) % 4]}) {
      const Eigen::Vector2d edge = (corner - other).normalized();
      Eigen::Vector2d normal(-edge.y(), edge.x());
      if (normal.dot(corner - centre) < 0.0) normal = -normal;  // outward
      normals.row(row++) = normal.transpose();
    }
    moved[k] = corner + normals.inverse() * Eigen::Vector2d(1.0, 1.0);
  }
  tag->corners = moved;
}

}  // namespace

void AprilGridOptions::Check() const {
  if (min_tags < 1) throw Error("AprilGrid options: min_tags must be >= 1");
  if (refine_half_window_px < 1) {
    throw Error("AprilGrid options: refine_half_window_px must be >= 1");
  }
  if (!(max_refine_shift_px > 0.0)) {
    throw Error("AprilGrid options: max_refine_shift_px must be > 0");
  }
}

BoardObservation DetectAprilGrid(const cv::Mat& image,
                                 const CalibrationBoard& board,
                                 const std::string& image_name,
                                 const AprilGridOptions& options,
                                 int* num_tags) {
  options.Check();
  if (board.kind != BoardKind::kAprilGrid) {
    throw ErrorAt(image_name, ": DetectAprilGrid needs an aprilgrid board");
  }
  if (image.empty() || image.depth() != CV_8U ||
      (image.channels() != 1 && image.channels() != 3)) {
    throw ErrorAt(image_name, ": expected an 8-bit grey or BGR image");
  }
  cv::Mat grey;
  if (image.channels() == 3) {
    cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  } else {
    grey = image;
  }
  cv::Mat dilated;
  cv::dilate(grey, dilated, cv::Mat::ones(3, 3, CV_8U));

  AprilTagOptions tags;
  tags.family = "tag36h11";
  tags.border_cells = 2;
  const int cols = board.grid_width / 2;
  const int rows = board.grid_height / 2;
  std::map<int, AprilTagDetection> found;  // by id; the first pass wins
  // Full resolution first: libapriltag 3.3's decimated corners are in a
  // slightly different pixel convention (cornerSubPix absorbs it).
  const std::pair<const cv::Mat*, double> passes[] = {
      {&grey, 1.0}, {&grey, 2.0}, {&dilated, 2.0}, {&dilated, 1.0}};
  for (const auto& [pass_image, decimate] : passes) {
    tags.quad_decimate = decimate;
    for (AprilTagDetection tag : DetectAprilTags(*pass_image, tags)) {
      if (tag.id < 0 || tag.id >= cols * rows) continue;
      if (pass_image == &dilated) UndoDilation(&tag);
      found.emplace(tag.id, tag);
    }
  }
  if (num_tags != nullptr) *num_tags = static_cast<int>(found.size());

  BoardObservation observation;
  observation.image = image_name;
  if (static_cast<int>(found.size()) < options.min_tags) return observation;
  observation.pixels.assign(board.NumCorners(), Eigen::Vector2d::Zero());
  observation.weights.assign(board.NumCorners(), -1.0);
  std::vector<cv::Point2f> to_refine;
  std::vector<int> indices;
  for (const auto& [id, tag] : found) {
    const int row = id / cols;
    const int col = id % cols;
    const int lower_left = 2 * row * board.grid_width + 2 * col;
    // libapriltag's lower left, lower right, upper right, upper left.
    const int index[4] = {lower_left, lower_left + 1,
                          lower_left + board.grid_width + 1,
                          lower_left + board.grid_width};
    for (int k = 0; k < 4; ++k) {
      to_refine.emplace_back(static_cast<float>(tag.corners[k].x()),
                             static_cast<float>(tag.corners[k].y()));
      indices.push_back(index[k]);
    }
  }
  std::vector<cv::Point2f> refined = to_refine;
  cv::cornerSubPix(
      grey, refined,
      cv::Size(options.refine_half_window_px, options.refine_half_window_px),
      cv::Size(-1, -1),
      cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 30,
                       1e-3));
  for (size_t i = 0; i < refined.size(); ++i) {
    if (cv::norm(refined[i] - to_refine[i]) > options.max_refine_shift_px) {
      continue;  // not an X-junction there: dropped, as Kalibr does
    }
    observation.pixels[indices[i]] =
        Eigen::Vector2d(refined[i].x, refined[i].y);
    observation.weights[indices[i]] = 1.0;
  }
  if (observation.NumFoundCorners() == 0) {
    observation.pixels.clear();
    observation.weights.clear();
  }
  return observation;
}

}  // namespace uw
