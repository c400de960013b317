#include "colmap_plugins/dense/pinhole_view.h"

#include <cmath>

#include <opencv2/imgproc.hpp>

#include "common/util/error.h"

namespace uw {

Eigen::Vector3d PinholeView::CamFromPixel(double x, double y,
                                          double depth) const {
  return depth *
         Eigen::Vector3d((x - K(0, 2)) / K(0, 0), (y - K(1, 2)) / K(1, 1), 1.0);
}

Eigen::Vector2d PinholeView::PixelFromCam(
    const Eigen::Vector3d& point_in_cam) const {
  return Eigen::Vector2d(
      K(0, 0) * point_in_cam.x() / point_in_cam.z() + K(0, 2),
      K(1, 1) * point_in_cam.y() / point_in_cam.z() + K(1, 2));
}

PinholeView MakePinholeView(const Camera& camera, const Rigid3d& cam_from_world,
                            const cv::Mat& image, double scale,
                            const std::string& name) {
  if (image.empty()) {
    throw ErrorAt(name, ": empty or unreadable image");
  }
  if (image.cols != static_cast<int>(camera.width) ||
      image.rows != static_cast<int>(camera.height)) {
    throw ErrorAt(name, ": image is ", image.cols, "x", image.rows,
                  " but its camera ", camera.camera_id, " is ", camera.width,
                  "x", camera.height);
  }
  if (!(scale > 0.0 && scale <= 1.0)) {
    throw ErrorAt(name, ": scale ", scale, " outside (0, 1]");
  }
  if (image.depth() != CV_8U && image.depth() != CV_16U) {
    throw ErrorAt(name, ": only 8- and 16-bit images are supported");
  }
  cv::Mat grey;
  if (image.channels() == 1) {
    grey = image;
  } else {
    cv::cvtColor(
        image, grey,
        image.channels() == 4 ? cv::COLOR_BGRA2GRAY : cv::COLOR_BGR2GRAY);
  }
  // Into a new matrix: `grey` may share the caller's pixels.
  cv::Mat levels;
  grey.convertTo(levels, CV_32F,
                 1.0 / (image.depth() == CV_16U ? 65535.0 : 255.0));
  grey = levels;

  const int width = std::max(
      1,
      static_cast<int>(std::lround(scale * static_cast<double>(camera.width))));
  const int height =
      std::max(1, static_cast<int>(
                      std::lround(scale * static_cast<double>(camera.height))));
  // Area averaging before resampling, so that a scaled-down view does not
  // alias the texture that matching relies on.
  cv::Mat source = grey;
  const double scale_x = static_cast<double>(width) / camera.width;
  const double scale_y = static_cast<double>(height) / camera.height;
  if (width != grey.cols || height != grey.rows) {
    cv::resize(grey, source, cv::Size(width, height), 0, 0, cv::INTER_AREA);
  }

  PinholeView view;
  view.cam_from_world = cam_from_world;
  const Eigen::Vector2d focal =
      CameraModelFocalLengths(camera.model_id, camera.params.data());
  const Eigen::Vector2d principal =
      CameraModelPrincipalPoint(camera.model_id, camera.params.data());
  view.K << scale_x * focal.x(), 0.0, scale_x * principal.x() - 0.5,  //
      0.0, scale_y * focal.y(), scale_y * principal.y() - 0.5,        //
      0.0, 0.0, 1.0;

  // For each output pixel: its ray, projected through the real camera
  // (COLMAP convention, full size), then into the scaled source (OpenCV
  // convention).
  cv::Mat map_x(height, width, CV_32F);
  cv::Mat map_y(height, width, CV_32F);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const Eigen::Vector2d pixel =
          camera.ImgFromCam(view.CamFromPixel(x, y, 1.0));
      map_x.at<float>(y, x) = static_cast<float>(scale_x * pixel.x() - 0.5);
      map_y.at<float>(y, x) = static_cast<float>(scale_y * pixel.y() - 0.5);
    }
  }
  cv::remap(source, view.grey, map_x, map_y, cv::INTER_LINEAR,
            cv::BORDER_CONSTANT, cv::Scalar(0.0));
  return view;
}

}  // namespace uw
