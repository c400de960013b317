#include "colmap_plugins/cameras/camera_models.h"

#include <algorithm>

namespace uw {

bool ExistsCameraModel(CameraModelId id) {
  return std::find(kAllCameraModelIds.begin(), kAllCameraModelIds.end(), id) !=
         kAllCameraModelIds.end();
}

CameraModelId CameraModelNameToId(const std::string& name) {
  for (const CameraModelId id : kAllCameraModelIds) {
    if (CameraModelIdToName(id) == name) {
      return id;
    }
  }
  return CameraModelId::kInvalid;
}

std::string CameraModelIdToName(CameraModelId id) {
  return VisitCameraModel(id, [](auto tag) -> std::string {
    return decltype(tag)::type::kModelName;
  });
}

int CameraModelNumParams(CameraModelId id) {
  if (!ExistsCameraModel(id)) {
    return -1;
  }
  return VisitCameraModel(
      id, [](auto tag) { return decltype(tag)::type::kNumParams; });
}

std::string CameraModelParamsInfo(CameraModelId id) {
  return VisitCameraModel(id, [](auto tag) -> std::string {
    return decltype(tag)::type::kParamsInfo;
  });
}

void CheckCameraModelParams(CameraModelId id, std::size_t num_params) {
  const int expected = CameraModelNumParams(id);
  if (expected < 0) {
    throw ErrorAt("unknown camera model id ", static_cast<int>(id));
  }
  if (num_params != static_cast<std::size_t>(expected)) {
    throw ErrorAt("camera model ", CameraModelIdToName(id), " expects ",
                  expected, " parameters, got ", num_params);
  }
}

Eigen::Vector2d CameraModelImgFromCam(CameraModelId id, const double* params,
                                      const Eigen::Vector3d& point_in_cam) {
  return VisitCameraModel(id, [&](auto tag) {
    Eigen::Vector2d pixel;
    decltype(tag)::type::ImgFromCam(params, point_in_cam.x(), point_in_cam.y(),
                                    point_in_cam.z(), &pixel.x(), &pixel.y());
    return pixel;
  });
}

Eigen::Vector3d CameraModelCamFromImg(CameraModelId id, const double* params,
                                      const Eigen::Vector2d& pixel) {
  return VisitCameraModel(id, [&](auto tag) {
    Eigen::Vector3d ray;
    decltype(tag)::type::CamFromImg(params, pixel.x(), pixel.y(), &ray.x(),
                                    &ray.y(), &ray.z());
    return ray;
  });
}

Eigen::Vector2d CameraModelFocalLengths(CameraModelId id,
                                        const double* params) {
  return VisitCameraModel(id, [&](auto tag) {
    using Model = typename decltype(tag)::type;
    return Eigen::Vector2d(params[Model::kFocalLengthIdxs.front()],
                           params[Model::kFocalLengthIdxs.back()]);
  });
}

Eigen::Vector2d CameraModelPrincipalPoint(CameraModelId id,
                                          const double* params) {
  return VisitCameraModel(id, [&](auto tag) {
    using Model = typename decltype(tag)::type;
    return Eigen::Vector2d(params[Model::kPrincipalPointIdxs[0]],
                           params[Model::kPrincipalPointIdxs[1]]);
  });
}

}  // namespace uw
