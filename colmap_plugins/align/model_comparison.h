// How far a model is from a reference model (another reconstruction, or
// uwsim's truth with its true surface): `uwcolmap model_comparer`.
//
// The model's camera centres are aligned to the reference's by a
// similarity over the images both have (by name), unless the model is
// already in the reference's frame, and everything below is measured after
// it: camera position and rotation errors, per-segment scale
// along the track, the deviation of the model's 3D points from the
// reference surface (binned along the track, with the dome fit), and the
// ratios of camera distances between the two models (before alignment).
// Images are taken in the order of their names (acquisition order for
// numbered frames) wherever consecutive images matter.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "colmap_plugins/align/mesh_distance.h"
#include "colmap_plugins/align/similarity.h"
#include "colmap_plugins/align/track_metrics.h"
#include "colmap_plugins/scene/model.h"

namespace uw {

struct ModelComparisonOptions {
  // false: the models are compared where they are, for a model already in
  // the reference's frame (aligned to navigation, or fused with it in the
  // bundle adjustment), whose absolute errors are then measured.
  bool align = true;
  // Least squares by default: a comparison should show every deviation
  // rather than set the worst cameras aside as outliers.
  // estimate_scale false: a rigid alignment.
  SimilarityOptions alignment = [] {
    SimilarityOptions options;
    options.robust = false;
    return options;
  }();
  int num_segments = 6;
  int num_bins = 12;
  // Points whose stored mean reprojection error exceeds this are left out
  // of the surface deviation (unknown errors, -1, are kept).
  double max_reprojection_error_px = 2.0;
  // Bins with fewer points take no part in the dome fit.
  size_t min_points_per_bin = 10;

  void Check() const;
};

struct CameraDeviation {
  std::string name;
  // Aligned model centre − reference centre, m (reference frame).
  Eigen::Vector3d position_error_m = Eigen::Vector3d::Zero();
  // Angle of the aligned model's rotation relative to the reference's.
  double rotation_error_deg = 0.0;
  double along_track_m = 0.0;  // of the reference centre
  bool inlier = true;          // of the alignment
};

struct SurfaceDeviation {
  size_t num_points = 0;       // 3D points of the model
  size_t num_points_used = 0;  // within max_reprojection_error_px
  // Signed distance from the reference surface, positive towards the
  // cameras that observe the point, m.
  double rms_m = 0.0;
  double mean_m = 0.0;
  double median_m = 0.0;
  double median_abs_m = 0.0;
  double p95_abs_m = 0.0;
  double max_abs_m = 0.0;
  // Over the along-track range of the reference cameras.
  std::vector<DeviationBin> bins;
  DomeFit dome;
};

struct ModelComparison {
  size_t num_model_images = 0;
  size_t num_reference_images = 0;
  // Reference images the model does not have (not registered, or named
  // differently), and the number of model images the reference lacks.
  std::vector<std::string> missing_images;
  size_t num_unmatched_model_images = 0;

  // reference_from_model over the common images (the identity, every image
  // an inlier, without alignment).
  bool aligned = true;
  SimilarityResult alignment;
  // Common images in name order.
  std::vector<CameraDeviation> cameras;
  double camera_rmse_m = 0.0;
  double camera_max_error_m = 0.0;
  double rotation_rmse_deg = 0.0;
  double rotation_max_deg = 0.0;
  // Diagonal of the box around the reference centres, m.
  double reference_extent_m = 0.0;

  TrackAxis axis;
  std::vector<SegmentScale> segments;
  // Model distances over reference distances, in each model's own frame.
  DistanceRatios distance_ratios;
  // With a reference surface only.
  std::optional<SurfaceDeviation> surface;
};

// Throws uw::Error when the models share fewer than 3 image names (the
// message gives an example name of each), or whatever EstimateSimilarity
// throws (collinear centres).
ModelComparison CompareModels(const Reconstruction& model,
                              const Reconstruction& reference,
                              const MeshDistance* reference_surface,
                              const ModelComparisonOptions& options);

// compare.json (docs/formats.md).
nlohmann::json ToJson(const ModelComparison& comparison);

// What model_comparer prints: images, alignment, camera errors, track,
// segments, distance ratios and, with a surface (read from
// `surface_path`), its deviation bins and dome fit.
std::string FormatModelComparison(const ModelComparison& comparison,
                                  const std::string& surface_path,
                                  const ModelComparisonOptions& options);

}  // namespace uw
