// How well a reconstructed surface (a dense mesh) matches the true one:
// accuracy (distance from the reconstruction to the truth) and completeness
// (the share of the surface the survey saw that the reconstruction covers),
// the two measures of multi-view stereo benchmarks (Seitz et al. 2006;
// Knapitsch et al. 2017), in the reference's units.
#pragma once

#include <cstdint>

#include <nlohmann/json.hpp>

#include "colmap_plugins/align/sim3.h"
#include "colmap_plugins/scene/model.h"
#include "common/mesh/mesh.h"

namespace uw {

struct MeshComparisonOptions {
  // Area-uniform samples on the reconstructed mesh for the accuracy.
  int num_samples = 200000;
  uint64_t seed = 1;
  // A true triangle is observed when this many reference images see its
  // centroid (in view, unoccluded): the least that can be reconstructed.
  int min_views = 2;
  // ...and covered when its centroid lies within this fraction of the
  // camera-scene distance of the reconstructed mesh.
  double coverage_tolerance = 0.01;
  // An image sees a true triangle only within this range (m) of its centre:
  // how far the water lets it see (uwsim states it in truth/sim.json,
  // truth.visible_range_m). 0: any range.
  double max_range_m = 0.0;

  void Check() const;  // throws uw::Error naming the bad field
};

struct MeshComparison {
  // Median over the reference images of the distance from the camera
  // centre along the optical axis to the reference surface.
  double camera_scene_distance = 0.0;
  size_t num_samples = 0;
  // Unsigned distances of the samples to the reference surface.
  double median = 0.0;
  double p90 = 0.0;
  double rms = 0.0;
  // Signed mean: positive when the reconstruction lies in front of the
  // truth, seen from the nearest camera.
  double mean_signed = 0.0;
  double observed_area = 0.0;
  double covered_area = 0.0;
  double coverage = 0.0;            // covered / observed
  double coverage_tolerance = 0.0;  // absolute
  int min_views = 0;                // as in the options
  double max_range_m = 0.0;         // as in the options
};

// `mesh` must already be in the reference's frame (see TransformMesh).
// Throws uw::Error for an empty mesh or when no reference image sees the
// reference surface.
MeshComparison CompareMeshes(const TriangleMesh& mesh,
                             const TriangleMesh& reference_mesh,
                             const Reconstruction& reference,
                             const MeshComparisonOptions& options);

// Vertices mapped by b_from_a.
TriangleMesh TransformMesh(const Sim3d& b_from_a, TriangleMesh mesh);

nlohmann::json ToJson(const MeshComparison& comparison);

// What model_comparer prints about the dense mesh read from `mesh_path`.
std::string FormatMeshComparison(const MeshComparison& comparison,
                                 const std::string& mesh_path);

}  // namespace uw
