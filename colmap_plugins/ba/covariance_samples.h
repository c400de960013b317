// Joint draws of a bundle adjustment's error (docs/covariance.md,
// "Samples"): what a downstream Monte Carlo (the laser scale) re-samples the
// model with, correlations between cameras, intrinsics and points kept. The
// marginals of covariance.bin cannot do that: a scale measured between two
// points depends on their cross-covariance as much as on their own.
//
// Each draw has the similarity that best maps its points onto the nominal
// ones removed: what remains is the model's deformation, which a
// measurement made inside the model errs by; the similarity's log scale is
// kept apart (with the priors gauge, the navigation's own scale error).
//
// samples.bin, beside covariance.bin, with the same model fingerprint (of
// the model's structure; covariance.bin also checks every image and point
// is where it was, which readers of the draws use to refuse a model
// adjusted since):
//   "UWSMP\0\0\1", fingerprint u64, counts (cameras, images, points,
//   samples) u64; per camera: id u32, n u32, n parameter indices u32; image
//   ids u32; point ids u64; then per draw: log scale f64, the camera deltas
//   f64, 6 f32 per image, 3 f32 per point. Float for the images and points:
//   their deltas are millimetres where float keeps 1e-7 of them.
#pragma once

#include <filesystem>
#include <ostream>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

#include "colmap_plugins/scene/model.h"

namespace uw {

struct CovarianceSamples {
  // What the rows of a draw are, in order.
  std::vector<camera_t> camera_ids;
  std::vector<std::vector<int>> camera_param_indices;  // refined parameters
  std::vector<image_t> image_ids;
  std::vector<point3D_t> point3D_ids;
  // One column per draw. log_scale: of the similarity removed. Camera rows:
  // the refined parameters' deltas, stacked in camera order. Image rows, 6
  // each: [world rotation vector w of world_from_cam, world_from_cam' =
  // Exp(w) world_from_cam (rad); centre (m)]. Point rows, 3 each (m).
  Eigen::VectorXd log_scale;
  Eigen::MatrixXd camera_deltas;
  Eigen::MatrixXf image_deltas;
  Eigen::MatrixXf point_deltas;

  int NumSamples() const { return static_cast<int>(log_scale.size()); }
  // First row of a camera's deltas (-1: its intrinsics were held), of a
  // point's (-1: not in the draws).
  int CameraRow(camera_t camera_id) const;
  int PointRow(point3D_t point3D_id) const;
  // Fills the lookups behind the *Row() functions; after the ids change.
  void Index();

 private:
  std::unordered_map<camera_t, int> camera_rows_;
  std::unordered_map<point3D_t, int> point_rows_;
};

// How a first-order similarity theta = (omega, tau, sigma), x' = x +
// omega x x + tau + sigma x, moves the point x: x' - x = A(x) theta, A(x) =
// [-[x]_x | I | x]. The gauge null space of a free network and the
// similarity removed from the draws are both made of it.
Eigen::Matrix<double, 3, 7> SimilarityTangentAt(const Eigen::Vector3d& x);

// Removes from each draw the first-order similarity (least squares, every
// point weighted alike) that maps its drawn points onto the nominal ones of
// `model`, from points and images alike, and stores that similarity's log
// scale (how much larger the drawn model is). Needs at least 3 points.
void SeparateSimilarity(const Reconstruction& model,
                        CovarianceSamples* samples);

void WriteCovarianceSamples(const CovarianceSamples& samples,
                            const Reconstruction& model, std::ostream& out);

// Reads samples.bin for `model`; throws uw::Error naming the file when it
// is not one, is truncated, or belongs to another model.
CovarianceSamples ReadCovarianceSamples(const std::filesystem::path& path,
                                        const Reconstruction& model);

}  // namespace uw
