#include "colmap_plugins/align/mesh_comparison.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "colmap_plugins/align/mesh_distance.h"
#include "colmap_plugins/align/visibility.h"
#include "common/mesh/ray_caster.h"
#include "common/util/error.h"
#include "common/util/random.h"

namespace uw {

void MeshComparisonOptions::Check() const {
  if (num_samples < 1) {
    throw ErrorAt("MeshComparison.num_samples must be >= 1, got ", num_samples);
  }
  if (min_views < 1) {
    throw ErrorAt("MeshComparison.min_views must be >= 1, got ", min_views);
  }
  if (!(max_range_m >= 0.0) || !std::isfinite(max_range_m)) {
    throw ErrorAt(
        "MeshComparison.max_range_m must be >= 0 (0: any range), "
        "got ",
        max_range_m);
  }
  if (!(coverage_tolerance > 0.0)) {
    throw ErrorAt("MeshComparison.coverage_tolerance must be > 0, got ",
                  coverage_tolerance);
  }
}

namespace {

double TriangleArea(const TriangleMesh& mesh, size_t t) {
  const Eigen::Vector3i& triangle = mesh.triangles[t];
  const Eigen::Vector3d& a = mesh.vertices[triangle[0]];
  return 0.5 * (mesh.vertices[triangle[1]] - a)
                   .cross(mesh.vertices[triangle[2]] - a)
                   .norm();
}

Eigen::Vector3d Centroid(const TriangleMesh& mesh, size_t t) {
  const Eigen::Vector3i& triangle = mesh.triangles[t];
  return (mesh.vertices[triangle[0]] + mesh.vertices[triangle[1]] +
          mesh.vertices[triangle[2]]) /
         3.0;
}

double Quantile(std::vector<double> values, double q) {
  const size_t k =
      static_cast<size_t>(q * static_cast<double>(values.size() - 1));
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[k];
}

}  // namespace

MeshComparison CompareMeshes(const TriangleMesh& mesh,
                             const TriangleMesh& reference_mesh,
                             const Reconstruction& reference,
                             const MeshComparisonOptions& options) {
  options.Check();
  if (mesh.triangles.empty()) {
    throw Error("mesh comparison: the reconstructed mesh has no triangles");
  }
  MeshComparison result;
  const RayCaster reference_caster(reference_mesh);

  std::vector<double> ranges;
  std::vector<Eigen::Vector3d> centres;
  for (const Image& image : reference.Images()) {
    const Eigen::Vector3d centre = image.ProjectionCenter();
    centres.push_back(centre);
    const Eigen::Vector3d axis =
        image.cam_from_world.RotationMatrix().row(2).transpose();
    const auto hit = reference_caster.Intersect(centre, axis.normalized());
    if (hit) {
      ranges.push_back(hit->distance);
    }
  }
  if (ranges.empty()) {
    throw Error(
        "mesh comparison: no reference image looks at the reference surface");
  }
  result.camera_scene_distance = Quantile(ranges, 0.5);
  result.coverage_tolerance =
      options.coverage_tolerance * result.camera_scene_distance;
  result.min_views = options.min_views;
  result.max_range_m = options.max_range_m;

  // Accuracy: area-uniform samples on the reconstruction, drawn in order
  // from one seeded stream so that they do not depend on threads.
  std::vector<double> cumulative(mesh.triangles.size());
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    cumulative[t] = (t == 0 ? 0.0 : cumulative[t - 1]) + TriangleArea(mesh, t);
  }
  if (!(cumulative.back() > 0.0)) {
    throw Error("mesh comparison: the reconstructed mesh has no area");
  }
  SplitMix64Stream random(options.seed);
  std::vector<Eigen::Vector3d> samples(options.num_samples);
  for (Eigen::Vector3d& sample : samples) {
    const double at = random.Uniform() * cumulative.back();
    const size_t t = std::min<size_t>(
        std::upper_bound(cumulative.begin(), cumulative.end(), at) -
            cumulative.begin(),
        mesh.triangles.size() - 1);
    double u = random.Uniform();
    double v = random.Uniform();
    if (u + v > 1.0) {
      u = 1.0 - u;
      v = 1.0 - v;
    }
    const Eigen::Vector3i& triangle = mesh.triangles[t];
    const Eigen::Vector3d& a = mesh.vertices[triangle[0]];
    sample = a + u * (mesh.vertices[triangle[1]] - a) +
             v * (mesh.vertices[triangle[2]] - a);
  }
  const MeshDistance reference_distance(reference_mesh.vertices,
                                        reference_mesh.triangles);
  std::vector<double> distances(samples.size());
  std::vector<double> signed_distances(samples.size());
  tbb::parallel_for(size_t{0}, samples.size(), [&](size_t i) {
    size_t nearest = 0;
    for (size_t c = 1; c < centres.size(); ++c) {
      if ((centres[c] - samples[i]).squaredNorm() <
          (centres[nearest] - samples[i]).squaredNorm()) {
        nearest = c;
      }
    }
    signed_distances[i] =
        reference_distance.SignedDistance(samples[i], centres[nearest]);
    distances[i] = std::abs(signed_distances[i]);
  });
  result.num_samples = samples.size();
  result.median = Quantile(distances, 0.5);
  result.p90 = Quantile(distances, 0.9);
  result.rms = std::sqrt(std::inner_product(distances.begin(), distances.end(),
                                            distances.begin(), 0.0) /
                         static_cast<double>(distances.size()));
  result.mean_signed =
      std::accumulate(signed_distances.begin(), signed_distances.end(), 0.0) /
      static_cast<double>(signed_distances.size());

  // Completeness over the true surface the survey saw.
  const SurfaceVisibility visibility(reference, reference_caster);
  const MeshDistance reconstructed(mesh.vertices, mesh.triangles);
  const size_t num_true = reference_mesh.triangles.size();
  std::vector<double> observed(num_true, 0.0);
  std::vector<double> covered(num_true, 0.0);
  std::vector<Eigen::Vector3d> image_centres;
  for (const Image& image : reference.Images()) {
    image_centres.push_back(image.ProjectionCenter());
  }
  tbb::parallel_for(size_t{0}, num_true, [&](size_t t) {
    const Eigen::Vector3d centroid = Centroid(reference_mesh, t);
    int views = 0;
    for (const SurfaceObservation& seen : visibility.Observe(centroid)) {
      views +=
          options.max_range_m <= 0.0 ||
          (image_centres[seen.view] - centroid).norm() <= options.max_range_m;
    }
    if (views < options.min_views) return;
    observed[t] = TriangleArea(reference_mesh, t);
    if (reconstructed.Query(centroid).distance <= result.coverage_tolerance) {
      covered[t] = observed[t];
    }
  });
  result.observed_area = std::accumulate(observed.begin(), observed.end(), 0.0);
  result.covered_area = std::accumulate(covered.begin(), covered.end(), 0.0);
  if (!(result.observed_area > 0.0)) {
    throw ErrorAt(
        "mesh comparison: no part of the reference surface is seen "
        "by ",
        options.min_views, " reference images");
  }
  result.coverage = result.covered_area / result.observed_area;
  return result;
}

TriangleMesh TransformMesh(const Sim3d& b_from_a, TriangleMesh mesh) {
  for (Eigen::Vector3d& vertex : mesh.vertices) {
    vertex = b_from_a * vertex;
  }
  return mesh;
}

nlohmann::json ToJson(const MeshComparison& comparison) {
  return {{"camera_scene_distance", comparison.camera_scene_distance},
          {"num_samples", comparison.num_samples},
          {"median_distance", comparison.median},
          {"p90_distance", comparison.p90},
          {"rms_distance", comparison.rms},
          {"mean_signed_distance", comparison.mean_signed},
          {"median_over_camera_scene_distance",
           comparison.median / comparison.camera_scene_distance},
          {"observed_area", comparison.observed_area},
          {"covered_area", comparison.covered_area},
          {"coverage", comparison.coverage},
          {"coverage_tolerance", comparison.coverage_tolerance},
          {"coverage_min_views", comparison.min_views},
          {"coverage_max_range", comparison.max_range_m}};
}

std::string FormatMeshComparison(const MeshComparison& comparison,
                                 const std::string& mesh_path) {
  return fmt::format(
      "Dense surface: {} (after the alignment)\n"
      "  camera-scene distance (median along the optical axes): {:.6g} m\n"
      "  distance to the reference surface over {} samples: median {:.6g} m "
      "({:.3f} % of the camera-scene distance), 90 % {:.6g} m, RMS {:.6g} m, "
      "signed mean {:.6g} m\n"
      "  coverage: {:.2f} % of the {:.6g} m^2 seen by >= {} reference images "
      "{}lie within {:.4g} m of the dense surface\n",
      mesh_path, comparison.camera_scene_distance, comparison.num_samples,
      comparison.median,
      100.0 * comparison.median / comparison.camera_scene_distance,
      comparison.p90, comparison.rms, comparison.mean_signed,
      100.0 * comparison.coverage, comparison.observed_area,
      comparison.min_views,
      comparison.max_range_m > 0.0
          ? fmt::format("within {:.3g} m (what the water lets them see) ",
                        comparison.max_range_m)
          : std::string(),
      comparison.coverage_tolerance);
}

}  // namespace uw
