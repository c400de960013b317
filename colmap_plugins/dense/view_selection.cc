#include "colmap_plugins/dense/view_selection.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

#include "common/util/error.h"

namespace uw {

void ViewSelectionOptions::Check() const {
  if (num_neighbors < 1 || num_neighbors > 16) {
    throw ErrorAt("ViewSelection.num_neighbors must be in [1, 16], got ",
                  num_neighbors);
  }
  if (min_shared_points < 1) {
    throw ErrorAt("ViewSelection.min_shared_points must be >= 1, got ",
                  min_shared_points);
  }
  if (!(min_triangulation_angle_deg >= 0.0 &&
        min_triangulation_angle_deg < max_triangulation_angle_deg &&
        max_triangulation_angle_deg <= 180.0)) {
    throw ErrorAt(
        "ViewSelection triangulation angles need 0 <= min < max <= 180, got ",
        min_triangulation_angle_deg, " and ", max_triangulation_angle_deg);
  }
  if (!(depth_quantile >= 0.0 && depth_quantile < 0.5)) {
    throw ErrorAt("ViewSelection.depth_quantile must be in [0, 0.5), got ",
                  depth_quantile);
  }
  if (!(depth_margin >= 0.0 && depth_margin < 1.0)) {
    throw ErrorAt("ViewSelection.depth_margin must be in [0, 1), got ",
                  depth_margin);
  }
}

namespace {

double Quantile(std::vector<double> values, double q) {
  const size_t k =
      static_cast<size_t>(q * static_cast<double>(values.size() - 1));
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[k];
}

}  // namespace

std::vector<ViewNeighbors> SelectViews(const Reconstruction& model,
                                       const ViewSelectionOptions& options) {
  options.Check();
  const std::vector<Image>& images = model.Images();
  std::unordered_map<image_t, size_t> index_of;
  std::vector<Eigen::Vector3d> centers;
  for (size_t i = 0; i < images.size(); ++i) {
    index_of[images[i].image_id] = i;
    centers.push_back(images[i].ProjectionCenter());
  }
  // Triangulation angles of every pair that shares a point, keyed by
  // (smaller index, larger index); std::map keeps the result independent of
  // hashing.
  std::map<std::pair<size_t, size_t>, std::vector<double>> pair_angles;
  std::vector<std::vector<double>> depths(images.size());
  for (const Point3D& point : model.Points3D()) {
    std::vector<size_t> seen_by;
    for (const TrackElement& element : point.track) {
      const auto found = index_of.find(element.image_id);
      if (found != index_of.end()) {
        seen_by.push_back(found->second);
      }
    }
    std::sort(seen_by.begin(), seen_by.end());
    seen_by.erase(std::unique(seen_by.begin(), seen_by.end()), seen_by.end());
    for (size_t a = 0; a < seen_by.size(); ++a) {
      const size_t i = seen_by[a];
      depths[i].push_back((images[i].cam_from_world * point.xyz).z());
      const Eigen::Vector3d ray_i = (point.xyz - centers[i]).normalized();
      for (size_t b = a + 1; b < seen_by.size(); ++b) {
        const size_t j = seen_by[b];
        const Eigen::Vector3d ray_j = (point.xyz - centers[j]).normalized();
        pair_angles[{i, j}].push_back(
            std::acos(std::clamp(ray_i.dot(ray_j), -1.0, 1.0)) * 180.0 / M_PI);
      }
    }
  }

  std::vector<std::vector<std::pair<double, size_t>>> scored(images.size());
  for (const auto& [pair, angles] : pair_angles) {
    if (static_cast<int>(angles.size()) < options.min_shared_points) {
      continue;
    }
    const double angle = Quantile(angles, 0.5);
    if (angle < options.min_triangulation_angle_deg ||
        angle > options.max_triangulation_angle_deg) {
      continue;
    }
    const double score =
        static_cast<double>(angles.size()) * std::min(1.0, angle / 10.0);
    scored[pair.first].push_back({score, pair.second});
    scored[pair.second].push_back({score, pair.first});
  }

  std::vector<ViewNeighbors> views(images.size());
  for (size_t i = 0; i < images.size(); ++i) {
    std::vector<std::pair<double, size_t>>& candidates = scored[i];
    std::sort(candidates.begin(), candidates.end(),
              [](const auto& a, const auto& b) {
                return a.first > b.first ||
                       (a.first == b.first && a.second < b.second);
              });
    for (size_t k = 0;
         k < candidates.size() && static_cast<int>(k) < options.num_neighbors;
         ++k) {
      views[i].neighbors.push_back(candidates[k].second);
    }
    std::vector<double>& image_depths = depths[i];
    image_depths.erase(
        std::remove_if(image_depths.begin(), image_depths.end(),
                       [](double depth) { return !(depth > 0.0); }),
        image_depths.end());
    if (image_depths.size() >= 10) {
      const double low = Quantile(image_depths, options.depth_quantile);
      const double high = Quantile(image_depths, 1.0 - options.depth_quantile);
      views[i].depth_range =
          std::make_pair((1.0 - options.depth_margin) * low,
                         (1.0 + options.depth_margin) * high);
    }
  }
  return views;
}

}  // namespace uw
