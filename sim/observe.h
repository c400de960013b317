// uwsim observe: the feature tracks a perfect matcher and mapper would give
// for a generated survey. Points are sampled on the true surface, observed
// by every image that sees them and projected with the true camera model
// plus Gaussian pixel noise of a known sigma. Bundle adjustment can then be
// tested against known pixel and navigation noise with no matcher between
// (docs/uwsim.md).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "colmap_plugins/align/sim3.h"
#include "colmap_plugins/scene/model.h"
#include "common/mesh/mesh.h"

namespace uw::sim {

// Where the observed model's poses and points start.
enum class ObserveInit {
  kTruth,      // the true poses and points
  kPerturbed,  // the truth moved by a random similarity, poses jittered
};
std::string ObserveInitName(ObserveInit init);
ObserveInit ObserveInitFromName(const std::string& name);  // throws uw::Error

struct ObserveOptions {
  // Standard deviation of the Gaussian noise added to each pixel coordinate.
  double pixel_sigma = 0.5;
  // Points wanted, each seen by at least two images. Sampling gives up after
  // kMaxCandidatesPerPoint x num_points candidates (a survey whose images
  // barely overlap), so the model may hold fewer.
  int num_points = 20000;
  uint64_t seed = 1;
  ObserveInit init = ObserveInit::kTruth;
  // kPerturbed: before the similarity, each camera turns by a random small
  // rotation with this standard deviation per axis and its centre moves by
  // this standard deviation per axis (world metres). Points are moved by the
  // similarity only, so the start is a consistent model with pose errors.
  double perturb_rotation_deg = 0.2;
  double perturb_position_m = 0.02;
  // As an incremental mapper registers an image only from enough points
  // that other images already triangulated (colmap's
  // Mapper.abs_pose_min_num_inliers, 30): when > 0, an image with fewer
  // points seen by three or more images is dropped with its observations,
  // until every image left has them. 0 keeps every image, including one
  // whose points only it and one other image see: its baselines are then
  // free, which no mapper's model holds.
  int min_registration_points = 0;

  static constexpr int kMaxCandidatesPerPoint = 50;
  void Check() const;
};

struct ObserveSummary {
  size_t num_candidates = 0;  // points sampled on the surface the images see
  size_t num_points = 0;      // kept: seen by >= 2 images
  size_t num_observations = 0;
  // Images dropped by min_registration_points, by name.
  std::vector<std::string> dropped_images;
  // The similarity that took the truth to the model (identity for kTruth).
  Sim3d model_from_world;
};

// The model a perfect matcher and mapper would give: the cameras and images
// of `truth` (same ids, names and cameras; its 2D points are ignored), each
// image's noisy 2D points with the ids of their 3D points, and the points
// with their tracks and mean reprojection errors. Points are sampled
// uniformly over the area of `mesh` whose triangles have their centroid in
// the view of some image, then kept by the images that see them: in front,
// projecting inside the image where the camera model is invertible, and the
// first surface along the ray from the camera centre. Deterministic for
// options.seed whatever the thread count.
Reconstruction ObserveModel(const Reconstruction& truth,
                            const TriangleMesh& mesh,
                            const ObserveOptions& options,
                            ObserveSummary* summary = nullptr);

// Reads truth/cameras.txt, truth/images.txt and truth/mesh.ply of an uwsim
// output folder and writes the observed model as COLMAP text to
// `output_dir`, which must be new or empty; nothing is written on error.
ObserveSummary ObserveSimulation(const std::filesystem::path& sim_dir,
                                 const std::filesystem::path& output_dir,
                                 const ObserveOptions& options);

}  // namespace uw::sim
