#include "calib/same_model_check.h"

#include <algorithm>
#include <cmath>

#include "common/util/error.h"

namespace uw {

void CheckPosesUseModelPoints(const std::vector<Eigen::Vector3d>& model_points,
                              const std::vector<LocalizedImage>& images,
                              const std::string& poses_where,
                              const std::string& model_where) {
  std::vector<Eigen::Vector3d> by_x = model_points;
  std::sort(by_x.begin(), by_x.end(),
            [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
              return a.x() < b.x();
            });
  const auto is_model_point = [&](const Eigen::Vector3d& point) {
    const double tolerance = 1e-9 * (1.0 + point.norm());
    auto it = std::lower_bound(
        by_x.begin(), by_x.end(), point.x() - tolerance,
        [](const Eigen::Vector3d& a, double x) { return a.x() < x; });
    for (; it != by_x.end() && it->x() <= point.x() + tolerance; ++it) {
      if ((*it - point).norm() <= tolerance) return true;
    }
    return false;
  };
  for (const LocalizedImage& image : images) {
    if (!image.success || image.inliers.empty()) continue;
    size_t found = 0;
    for (const Correspondence2D3D& inlier : image.inliers) {
      found += is_model_point(inlier.point_in_world);
    }
    if (2 * found < image.inliers.size()) {
      throw ErrorAt(poses_where, ": image ", image.name, ": ",
                    image.inliers.size() - found, " of its ",
                    image.inliers.size(), " inlier points are not points of ",
                    model_where,
                    "; it was localized against another model, whose scale "
                    "differs (localize the images against this model)");
    }
  }
}

void CheckMeshFitsPoses(const RayCaster& caster,
                        const std::vector<LocalizedImage>& images,
                        const std::string& mesh_where, double max_ratio_error) {
  std::vector<double> ratios;
  size_t num_rays = 0;
  for (const LocalizedImage& image : images) {
    if (!image.success || image.inliers.empty()) continue;
    const Rigid3d world_from_cam = image.cam_from_world.Inverse();
    const Eigen::Vector3d centre = world_from_cam.translation;
    const size_t step = std::max<size_t>(1, image.inliers.size() / 20);
    for (size_t k = 0; k < image.inliers.size(); k += step) {
      const Eigen::Vector3d& point = image.inliers[k].point_in_world;
      const double distance = (point - centre).norm();
      if (!(distance > 0.0)) continue;
      ++num_rays;
      const auto hit = caster.Intersect(centre, (point - centre) / distance);
      if (hit) ratios.push_back(hit->distance / distance);
    }
  }
  if (num_rays == 0) return;  // nothing localized: nothing to compare
  if (2 * ratios.size() < num_rays) {
    throw ErrorAt(mesh_where, ": ", num_rays - ratios.size(), " of ", num_rays,
                  " rays through the localized images' inlier points miss "
                  "the mesh; it is not the surface of their model");
  }
  std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2,
                   ratios.end());
  const double median = ratios[ratios.size() / 2];
  if (std::abs(median - 1.0) > max_ratio_error) {
    throw ErrorAt(mesh_where,
                  ": rays through the localized images' inlier points meet "
                  "the mesh at ",
                  median,
                  " times the points' distance (median); it is not the "
                  "surface of their model (another model's mesh is off by "
                  "the ratio of the scales)");
  }
}

}  // namespace uw
