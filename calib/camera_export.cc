#include "calib/camera_export.h"

#include <opencv2/core.hpp>

#include "common/util/error.h"

namespace uw {
namespace {

// OpenCV's distortion coefficients of an mrcal OpenCV model (the same order
// and meaning), or throws for a model without them.
std::vector<double> OpenCvDistortion(const MrcalCameraModel& model,
                                     const std::string& where) {
  const std::string& name = model.lens_model;
  if (name == "LENSMODEL_PINHOLE") return {};
  if (name == "LENSMODEL_OPENCV4" || name == "LENSMODEL_OPENCV5" ||
      name == "LENSMODEL_OPENCV8" || name == "LENSMODEL_OPENCV12") {
    return std::vector<double>(model.intrinsics.begin() + 4,
                               model.intrinsics.end());
  }
  throw ErrorAt(where, ": ", name,
                " has no OpenCV or COLMAP equivalent (stereographic, "
                "lonlat/latlon, CAHVOR(E) and splined models project "
                "differently); calibrate with LENSMODEL_OPENCV4, OPENCV5 or "
                "OPENCV8 to export");
}

}  // namespace

Camera ColmapCameraFromMrcal(const MrcalCameraModel& model,
                             const std::string& where) {
  const std::vector<double> distortion = OpenCvDistortion(model, where);
  if (model.intrinsics.size() < 4 || model.image_width <= 0 ||
      model.image_height <= 0) {
    throw ErrorAt(where, ": incomplete camera model");
  }
  Camera camera;
  camera.width = static_cast<uint64_t>(model.image_width);
  camera.height = static_cast<uint64_t>(model.image_height);
  camera.params = {model.intrinsics[0], model.intrinsics[1],
                   model.intrinsics[2] + 0.5, model.intrinsics[3] + 0.5};
  if (distortion.empty()) {
    camera.model_id = CameraModelId::kPinhole;
  } else if (distortion.size() == 4) {
    camera.model_id = CameraModelId::kOpenCV;
    camera.params.insert(camera.params.end(), distortion.begin(),
                         distortion.end());
  } else {
    for (size_t i = 8; i < distortion.size(); ++i) {
      if (distortion[i] != 0.0) {
        throw ErrorAt(where, ": ", model.lens_model,
                      " has thin-prism terms (s1..s4 = ", distortion[8], ", ",
                      distortion[9], ", ", distortion[10], ", ", distortion[11],
                      ") that no COLMAP model has; calibrate with "
                      "LENSMODEL_OPENCV8 for COLMAP's FULL_OPENCV");
      }
    }
    camera.model_id = CameraModelId::kFullOpenCV;
    for (size_t i = 0; i < 8; ++i) {
      camera.params.push_back(i < distortion.size() ? distortion[i] : 0.0);
    }
  }
  return camera;
}

std::string OpenCvYamlFromMrcal(const MrcalCameraModel& model,
                                const std::string& where) {
  const std::vector<double> distortion = OpenCvDistortion(model, where);
  cv::FileStorage storage(".yaml", cv::FileStorage::WRITE |
                                       cv::FileStorage::MEMORY |
                                       cv::FileStorage::FORMAT_YAML);
  storage << "image_width" << model.image_width;
  storage << "image_height" << model.image_height;
  const cv::Matx33d camera_matrix(model.intrinsics[0], 0.0, model.intrinsics[2],
                                  0.0, model.intrinsics[1], model.intrinsics[3],
                                  0.0, 0.0, 1.0);
  storage << "camera_matrix" << cv::Mat(camera_matrix);
  cv::Mat coefficients(1, static_cast<int>(distortion.size()), CV_64F);
  for (size_t i = 0; i < distortion.size(); ++i) {
    coefficients.at<double>(0, static_cast<int>(i)) = distortion[i];
  }
  storage << "distortion_coefficients" << coefficients;
  storage << "lens_model" << model.lens_model;
  return storage.releaseAndGetString();
}

}  // namespace uw
