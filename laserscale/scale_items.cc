#include "laserscale/scale_items.h"

#include <cmath>

#include "colmap_plugins/cameras/camera_models.h"
#include "common/util/error.h"
#include "laserscale/scale_estimators.h"
#include "laserscale/spot_ray.h"

namespace uw {

std::string ScaleMethodName(ScaleMethod method) {
  switch (method) {
    case ScaleMethod::kFum:
      return "fum";
    case ScaleMethod::kPcm:
      return "pcm";
    case ScaleMethod::kDirect:
      return "direct";
    case ScaleMethod::kDavisTusting:
      return "davis_tusting";
  }
  throw ErrorAt("unknown scale method ", static_cast<int>(method));
}

ScaleMethod ScaleMethodFromName(const std::string& name) {
  for (const ScaleMethod method :
       {ScaleMethod::kFum, ScaleMethod::kPcm, ScaleMethod::kDirect,
        ScaleMethod::kDavisTusting}) {
    if (ScaleMethodName(method) == name) return method;
  }
  throw ErrorAt("unknown scale method '", name,
                "' (fum, pcm, direct or davis_tusting)");
}

std::vector<ScaleItem> ScaleItems(ScaleMethod method, const LaserSetup& setup,
                                  double pcm_equidistance_m) {
  const std::vector<Laser>& lasers = setup.lasers;
  std::vector<ScaleItem> items;
  const int n = static_cast<int>(lasers.size());
  switch (method) {
    case ScaleMethod::kFum:
      for (int i = 0; i < n; ++i) items.push_back({lasers[i].name, {i}, 0.0});
      break;
    case ScaleMethod::kPcm:
    case ScaleMethod::kDirect:
      for (int i = 0; i < n; ++i) {
        for (int j = i + 1; j < n; ++j) {
          const Eigen::Vector3d between =
              lasers[j].origin_in_cam - lasers[i].origin_in_cam;
          ScaleItem item{lasers[i].name + "-" + lasers[j].name, {i, j}, 0.0};
          if (method == ScaleMethod::kDirect) {
            item.known_length_m = between.norm();
          } else {
            if (std::abs(lasers[i].origin_in_cam.norm() -
                         lasers[j].origin_in_cam.norm()) > pcm_equidistance_m) {
              continue;
            }
            const Eigen::Vector3d direction =
                (lasers[i].direction_in_cam + lasers[j].direction_in_cam)
                    .normalized();
            item.known_length_m =
                (between - between.dot(direction) * direction).norm();
          }
          items.push_back(item);
        }
      }
      break;
    case ScaleMethod::kDavisTusting: {
      ScaleItem item{"all", {}, 0.0};
      for (int i = 0; i < n; ++i) item.lasers.push_back(i);
      items.push_back(item);
      break;
    }
  }
  if (items.empty()) {
    throw ErrorAt("laser set-up ", setup.name, ": ", ScaleMethodName(method),
                  " has nothing to measure (PCM needs two lasers whose "
                  "origins are equidistant from the optical centre)");
  }
  return items;
}

std::vector<ItemScale> EvaluateItems(ScaleMethod method,
                                     const std::vector<ScaleItem>& items,
                                     const std::vector<Laser>& lasers,
                                     const RayCaster& caster,
                                     const Camera& camera,
                                     const Rigid3d& cam_from_world,
                                     const SpotPixels& spots) {
  // Each laser's hit, cast once and shared by the items that use it.
  std::vector<SpotHit> hits(lasers.size());
  std::vector<bool> cast(lasers.size(), false);
  const auto hit_of = [&](int laser) -> const SpotHit& {
    if (!cast[laser]) {
      cast[laser] = true;
      if (!spots[laser]) {
        hits[laser].problem = "laser " + lasers[laser].name + " has no spot";
      } else {
        hits[laser] = CastSpot(caster, camera, cam_from_world, *spots[laser]);
        if (!hits[laser].point_in_world) {
          hits[laser].problem =
              "laser " + lasers[laser].name + ": " + hits[laser].problem;
        }
      }
    }
    return hits[laser];
  };
  const Eigen::Vector3d camera_center = cam_from_world.Inverse().translation;
  std::vector<ItemScale> scales;
  for (const ScaleItem& item : items) {
    ItemScale result;
    std::vector<Eigen::Vector3d> points;
    for (const int laser : item.lasers) {
      const SpotHit& hit = hit_of(laser);
      if (!hit.point_in_world) {
        result.problem = hit.problem;
        break;
      }
      points.push_back(*hit.point_in_world);
    }
    if (result.problem.empty()) {
      ScaleEstimate estimate;
      switch (method) {
        case ScaleMethod::kFum:
          estimate =
              FumScale(lasers[item.lasers[0]], cam_from_world * points[0]);
          break;
        case ScaleMethod::kPcm:
          estimate = PcmScale(points[0], points[1], camera_center,
                              item.known_length_m);
          break;
        case ScaleMethod::kDirect:
          estimate = DirectScale(points[0], points[1], item.known_length_m);
          break;
        case ScaleMethod::kDavisTusting: {
          std::vector<Laser> used;
          std::vector<Eigen::Vector2d> normalized;
          for (const int laser : item.lasers) {
            used.push_back(lasers[laser]);
            normalized.push_back(CameraModelCamFromImg(camera.model_id,
                                                       camera.params.data(),
                                                       *spots[laser])
                                     .head<2>());
          }
          estimate = DavisTustingScale(used, normalized, points);
          break;
        }
      }
      result.scale = estimate.scale;
      result.problem = estimate.problem;
    }
    scales.push_back(result);
  }
  return scales;
}

}  // namespace uw
