#include "sim/board_images.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "colmap_plugins/cameras/camera_models.h"
#include "common/util/error.h"
#include "common/util/random.h"

namespace uw::sim {
namespace {

constexpr double kDegree = 3.14159265358979323846 / 180.0;

// Level of the board at (x, y) on its plane.
double BoardLevel(double x, double y, const CalibrationBoard& board,
                  const BoardImageOptions& options) {
  const double s = board.spacing_m;
  // Squares run from -1 to grid_width (x) and -1 to grid_height (y).
  const double i = std::floor(x / s);
  const double j = std::floor(y / s);
  if (i >= -1 && i <= board.grid_width - 1 && j >= -1 &&
      j <= board.grid_height - 1) {
    const bool black =
        (static_cast<int64_t>(i) + static_cast<int64_t>(j)) % 2 == 0;
    return black ? options.black_level : options.white_level;
  }
  const double margin = (1.0 + options.margin_squares) * s;
  if (x >= -margin && x <= (board.grid_width - 1) * s + margin &&
      y >= -margin && y <= (board.grid_height - 1) * s + margin) {
    return options.white_level;
  }
  return options.background_level;
}

}  // namespace

BoardImage RenderBoardImage(const Camera& camera, const Rigid3d& cam_from_board,
                            const CalibrationBoard& board,
                            const BoardImageOptions& options, uint64_t seed) {
  if (options.supersampling < 1) {
    throw Error("RenderBoardImage: supersampling must be >= 1");
  }
  const int width = static_cast<int>(camera.width);
  const int height = static_cast<int>(camera.height);
  const Rigid3d board_from_cam = cam_from_board.Inverse();
  const Eigen::Matrix3d rotation = board_from_cam.RotationMatrix();
  const Eigen::Vector3d origin = board_from_cam.translation;
  const int n = options.supersampling;

  BoardImage result;
  result.image.create(height, width, CV_8UC1);
  for (int row = 0; row < height; ++row) {
    SplitMix64Stream noise(
        SplitMix64(seed ^ (0x9E3779B97F4A7C15ull * (row + 1))));
    for (int col = 0; col < width; ++col) {
      double sum = 0.0;
      for (int a = 0; a < n; ++a) {
        for (int b = 0; b < n; ++b) {
          // COLMAP pixel coordinates: the pixel (col, row) spans
          // [col, col + 1) x [row, row + 1).
          const Eigen::Vector2d pixel(col + (b + 0.5) / n, row + (a + 0.5) / n);
          const Eigen::Vector3d ray =
              rotation * CameraModelCamFromImg(camera.model_id,
                                               camera.params.data(), pixel);
          double level = options.background_level;
          if (std::abs(ray.z()) > 1e-12) {
            const double t = -origin.z() / ray.z();
            if (t > 0.0) {
              const Eigen::Vector3d hit = origin + t * ray;
              level = BoardLevel(hit.x(), hit.y(), board, options);
            }
          }
          sum += level;
        }
      }
      double value = sum / (n * n);
      if (options.noise_sigma > 0.0)
        value += options.noise_sigma * noise.Gaussian();
      result.image.at<uint8_t>(row, col) =
          static_cast<uint8_t>(std::clamp(std::round(value), 0.0, 255.0));
    }
  }
  result.all_corners_inside = true;
  for (const Eigen::Vector3d& corner : board.CornersInBoard()) {
    const Eigen::Vector3d in_cam = cam_from_board * corner;
    const Eigen::Vector2d pixel =
        camera.ImgFromCam(in_cam) - Eigen::Vector2d(0.5, 0.5);
    result.corners.push_back(pixel);
    if (in_cam.z() <= 0.0 || pixel.x() < 2.0 || pixel.y() < 2.0 ||
        pixel.x() > width - 3.0 || pixel.y() > height - 3.0) {
      result.all_corners_inside = false;
    }
  }
  return result;
}

std::vector<Rigid3d> RandomBoardPoses(const Camera& camera,
                                      const CalibrationBoard& board, int count,
                                      double min_distance_m,
                                      double max_distance_m,
                                      double max_tilt_deg, uint64_t seed) {
  SplitMix64Stream random(seed);
  const Eigen::Vector3d centre_in_board(
      0.5 * (board.grid_width - 1) * board.spacing_m,
      0.5 * (board.grid_height - 1) * board.spacing_m, 0.0);
  const double margin = 0.06 * std::min(camera.width, camera.height);
  std::vector<Rigid3d> poses;
  for (int attempt = 0; static_cast<int>(poses.size()) < count; ++attempt) {
    if (attempt > 1000 * count) {
      throw Error("RandomBoardPoses: the board does not fit the image");
    }
    // A viewing direction within the image, a distance, a tilt and a spin.
    const Eigen::Vector2d target(random.Uniform(0.25, 0.75) * camera.width,
                                 random.Uniform(0.25, 0.75) * camera.height);
    Eigen::Vector3d direction =
        CameraModelCamFromImg(camera.model_id, camera.params.data(), target);
    direction.normalize();
    const double distance = random.Uniform(min_distance_m, max_distance_m);
    const double tilt = random.Uniform(0.0, max_tilt_deg) * kDegree;
    const double tilt_axis = random.Uniform(0.0, 2.0 * 3.14159265358979323846);
    const double spin = random.Uniform(-20.0, 20.0) * kDegree;
    // Board z toward the camera's -z (its front faces the camera), tilted.
    const Eigen::Matrix3d facing =
        (Eigen::AngleAxisd(tilt, Eigen::Vector3d(std::cos(tilt_axis),
                                                 std::sin(tilt_axis), 0.0)) *
         Eigen::AngleAxisd(spin, Eigen::Vector3d::UnitZ()))
            .toRotationMatrix();
    Rigid3d cam_from_board;
    cam_from_board.rotation = Eigen::Quaterniond(facing);
    cam_from_board.translation =
        distance * direction - facing * centre_in_board;
    // The board's white margin and every inner corner must be in the image.
    const double s = board.spacing_m;
    const double out = (1.0 + BoardImageOptions().margin_squares) * s;
    std::vector<Eigen::Vector3d> checks = board.CornersInBoard();
    for (const double x : {-out, (board.grid_width - 1) * s + out}) {
      for (const double y : {-out, (board.grid_height - 1) * s + out}) {
        checks.emplace_back(x, y, 0.0);
      }
    }
    bool inside = true;
    for (const Eigen::Vector3d& point : checks) {
      const Eigen::Vector3d in_cam = cam_from_board * point;
      const Eigen::Vector2d pixel = in_cam.z() > 0.0 ? camera.ImgFromCam(in_cam)
                                                     : Eigen::Vector2d(-1, -1);
      if (pixel.x() < margin || pixel.y() < margin ||
          pixel.x() > camera.width - margin ||
          pixel.y() > camera.height - margin) {
        inside = false;
        break;
      }
    }
    if (inside) poses.push_back(cam_from_board);
  }
  return poses;
}

}  // namespace uw::sim
