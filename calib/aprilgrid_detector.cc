#include "calib/aprilgrid_detector.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include <Eigen/LU>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <apriltag/apriltag.h>
#include <apriltag/tag36h11.h>

#include "calib/apriltag_detector.h"
#include "calib/grey_image.h"
#include "common/util/error.h"

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

// Kalibr's position of corner index `k` of the grid, in tag sides.
Eigen::Vector2d CornerInBoard(const CalibrationBoard& board, int k) {
  const auto position = [&](int c) {
    return (c / 2) * (1.0 + board.tag_gap) + (c % 2);
  };
  return {position(k % board.grid_width), position(k / board.grid_width)};
}

// The corner indices of tag `id`: libapriltag's order (lower left, lower
// right, upper right, upper left).
std::array<int, 4> TagCorners(const CalibrationBoard& board, int id) {
  const int cols = board.grid_width / 2;
  const int lower_left = 2 * (id / cols) * board.grid_width + 2 * (id % cols);
  return {lower_left, lower_left + 1, lower_left + board.grid_width + 1,
          lower_left + board.grid_width};
}

// The bits a tag at `corners` shows, read as libapriltag reads them (cell
// centres through the tag's homography, threshold halfway between its
// black border and the white just outside it), against tag `id`'s code:
// the number of bits that differ.
int CodeDistance(const cv::Mat& grey,
                 const std::array<Eigen::Vector2d, 4>& corners,
                 const apriltag_family_t& stock, int id) {
  const int width = stock.width_at_border + 2;  // Kalibr: 2-cell border
  std::vector<cv::Point2f> tag = {{-1, 1}, {1, 1}, {1, -1}, {-1, -1}};
  std::vector<cv::Point2f> image;
  for (const Eigen::Vector2d& corner : corners) {
    image.emplace_back(static_cast<float>(corner.x()),
                       static_cast<float>(corner.y()));
  }
  const cv::Mat homography = cv::getPerspectiveTransform(tag, image);
  const auto sample = [&](double cell_x, double cell_y) {
    std::vector<cv::Point2f> in = {
        {static_cast<float>(2.0 * (cell_x / width - 0.5)),
         static_cast<float>(2.0 * (cell_y / width - 0.5))}};
    std::vector<cv::Point2f> out;
    cv::perspectiveTransform(in, out, homography);
    cv::Mat pixel;
    cv::getRectSubPix(grey, cv::Size(1, 1), out[0], pixel, CV_32F);
    return static_cast<double>(pixel.at<float>(0, 0));
  };
  double black = 0.0;
  double white = 0.0;
  int count = 0;
  for (int i = 2; i < width - 2; ++i) {
    const double c = i + 0.5;
    black += sample(0.5, c) + sample(width - 0.5, c) + sample(c, 0.5) +
             sample(c, width - 0.5);
    white += sample(-0.5, c) + sample(width + 0.5, c) + sample(c, -0.5) +
             sample(c, width + 0.5);
    count += 4;
  }
  const double threshold = 0.5 * (black + white) / count;
  if (white <= black) return static_cast<int>(stock.nbits);
  uint64_t code = 0;
  for (uint32_t i = 0; i < stock.nbits; ++i) {
    code = (code << 1) | (sample(stock.bit_x[i] + 1 + 0.5,
                                 stock.bit_y[i] + 1 + 0.5) > threshold
                              ? 1
                              : 0);
  }
  return __builtin_popcountll(code ^ stock.codes[id]);
}

// The code of a tag whose corners were predicted at `predicted`: the
// corners are first moved onto the X-junctions they sit near (in a window
// of a tenth of the tag, else of a fifth), so the code is read where the
// tag is and the next prediction starts from true corners; the prediction
// itself is the last try. Returns the bits off tag->id's code, and sets
// tag->corners to where they were read.
int ReadAt(const cv::Mat& grey, const std::vector<cv::Point2f>& predicted,
           const apriltag_family_t& stock, AprilTagDetection* tag) {
  const double side = cv::norm(predicted[2] - predicted[0]) / std::sqrt(2.0);
  for (const double fraction : {0.1, 0.2}) {
    const int half_window = std::max(2, static_cast<int>(fraction * side));
    std::vector<cv::Point2f> refined = predicted;
    cv::cornerSubPix(
        grey, refined, cv::Size(half_window, half_window), cv::Size(-1, -1),
        cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 30,
                         1e-3));
    for (int k = 0; k < 4; ++k) {
      const cv::Point2f& p = cv::norm(refined[k] - predicted[k]) <= half_window
                                 ? refined[k]
                                 : predicted[k];
      tag->corners[k] = Eigen::Vector2d(p.x, p.y);
    }
    const int distance = CodeDistance(grey, tag->corners, stock, tag->id);
    if (distance <= 2) return distance;
  }
  for (int k = 0; k < 4; ++k) {
    tag->corners[k] = Eigen::Vector2d(predicted[k].x, predicted[k].y);
  }
  return CodeDistance(grey, tag->corners, stock, tag->id);
}

// Grid completion: each missing tag with found neighbours (2 tags within
// one row and column, else within two) is predicted by the homography of
// their corners, and kept
// if the image there shows its code (at most 2 bits off, as libapriltag
// accepts). Repeated while tags are added.
void CompleteGrid(const cv::Mat& grey, const CalibrationBoard& board,
                  std::map<int, AprilTagDetection>* found) {
  apriltag_family_t* stock = tag36h11_create();
  const int cols = board.grid_width / 2;
  const int rows = board.grid_height / 2;
  bool added = true;
  while (added) {
    added = false;
    for (int id = 0; id < cols * rows; ++id) {
      if (found->count(id) != 0) continue;
      // The nearest ring of found tags that has at least 2 of them: a local
      // homography (lenses bend the grid).
      std::vector<cv::Point2f> in_board;
      std::vector<cv::Point2f> in_image;
      for (int radius = 1; radius <= 2 && in_board.size() < 8; ++radius) {
        in_board.clear();
        in_image.clear();
        for (const auto& [other, tag] : *found) {
          if (std::abs(other / cols - id / cols) > radius ||
              std::abs(other % cols - id % cols) > radius) {
            continue;
          }
          const std::array<int, 4> indices = TagCorners(board, other);
          for (int k = 0; k < 4; ++k) {
            const Eigen::Vector2d position = CornerInBoard(board, indices[k]);
            in_board.emplace_back(static_cast<float>(position.x()),
                                  static_cast<float>(position.y()));
            in_image.emplace_back(static_cast<float>(tag.corners[k].x()),
                                  static_cast<float>(tag.corners[k].y()));
          }
        }
      }
      if (in_board.size() < 8) continue;  // 2 tags at least
      const cv::Mat homography = cv::findHomography(in_board, in_image, 0);
      if (homography.empty()) continue;
      const std::array<int, 4> indices = TagCorners(board, id);
      std::vector<cv::Point2f> positions;
      for (const int index : indices) {
        const Eigen::Vector2d position = CornerInBoard(board, index);
        positions.emplace_back(static_cast<float>(position.x()),
                               static_cast<float>(position.y()));
      }
      std::vector<cv::Point2f> predicted;
      cv::perspectiveTransform(positions, predicted, homography);
      const auto inside = [&](const std::vector<cv::Point2f>& quad) {
        for (const cv::Point2f& p : quad) {
          if (!(p.x > 2 && p.y > 2 && p.x < grey.cols - 3 &&
                p.y < grey.rows - 3)) {
            return false;
          }
        }
        return true;
      };
      if (!inside(predicted)) continue;
      AprilTagDetection tag;
      tag.id = id;
      int distance = ReadAt(grey, predicted, *stock, &tag);
      // Where even the nearest tags' homography misses by a cell or two (a
      // grid's corner at a fish-eye's edge), the quad is tried shifted by
      // half cells, up to two cells each way, nearest first. A chance read
      // of a 36h11 code within 2 bits is about 1e-8 a try.
      const int cells = stock->width_at_border + 2;
      const cv::Point2f along_x = (predicted[1] - predicted[0]) / cells;
      const cv::Point2f along_y = (predicted[3] - predicted[0]) / cells;
      std::vector<cv::Point2f> shifts;
      for (int i = -4; i <= 4; ++i) {
        for (int j = -4; j <= 4; ++j) {
          if (i != 0 || j != 0) shifts.emplace_back(0.5f * i, 0.5f * j);
        }
      }
      std::stable_sort(shifts.begin(), shifts.end(),
                       [](const cv::Point2f& a, const cv::Point2f& b) {
                         return a.dot(a) < b.dot(b);
                       });
      for (size_t n = 0; n < shifts.size() && distance > 2; ++n) {
        std::vector<cv::Point2f> shifted = predicted;
        for (cv::Point2f& p : shifted) {
          p += shifts[n].x * along_x + shifts[n].y * along_y;
        }
        if (inside(shifted)) distance = ReadAt(grey, shifted, *stock, &tag);
      }
      if (distance > 2) continue;
      tag.hamming = distance;
      found->emplace(id, tag);
      added = true;
    }
  }
  tag36h11_destroy(stock);
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
  const cv::Mat grey = GreyImage(image, image_name);
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
  if (static_cast<int>(found.size()) >= 3) CompleteGrid(grey, board, &found);
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
