// One image of a model resampled for dense matching: grey, undistorted into a
// pinhole camera with the image's own focal lengths and principal point, and
// optionally scaled down. Every COLMAP camera model is handled by its own
// projection, so no OpenCV distortion model has to match COLMAP's.
//
// Pixel convention inside dense/: OpenCV's (the centre of pixel (0, 0) is at
// (0, 0)), because the homographies and warps are OpenCV's. COLMAP puts that
// centre at (0.5, 0.5); MakePinholeView converts once, in K.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "colmap_plugins/scene/model.h"

namespace uw {

struct PinholeView {
  // CV_32F grey levels in [0, 1]; 0 where the pinhole sees outside the
  // source image.
  cv::Mat grey;
  // Intrinsics in OpenCV's pixel convention.
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();
  Rigid3d cam_from_world;

  int Width() const { return grey.cols; }
  int Height() const { return grey.rows; }
  // The point at `depth` (along z) behind pixel (x, y).
  Eigen::Vector3d CamFromPixel(double x, double y, double depth) const;
  // Pixel of a point in this camera's frame (z > 0).
  Eigen::Vector2d PixelFromCam(const Eigen::Vector3d& point_in_cam) const;
};

// `image` is the file as cv::imread reads it (grey, BGR or BGRA, 8 or 16
// bit; other depths are an error) and must have the camera's size; `scale` in
// (0, 1] sets the output size to round(scale * width) x round(scale * height).
// Throws uw::Error naming `name` for a wrong size or an empty image.
PinholeView MakePinholeView(const Camera& camera, const Rigid3d& cam_from_world,
                            const cv::Mat& image, double scale,
                            const std::string& name);

}  // namespace uw
