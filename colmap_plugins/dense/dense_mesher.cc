#include "colmap_plugins/dense/dense_mesher.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>

#include "common/util/error.h"

namespace uw {

void DenseMesherOptions::Check() const {
  if (max_image_size != -1 && max_image_size < 16) {
    throw ErrorAt("DenseMesher.max_image_size must be -1 or >= 16, got ",
                  max_image_size);
  }
  view_selection.Check();
  plane_sweep.Check();
  if (!(voxel_size_factor > 0.0)) {
    throw ErrorAt("DenseMesher.voxel_size_factor must be > 0, got ",
                  voxel_size_factor);
  }
  if (num_threads == 0 || num_threads < -1) {
    throw ErrorAt("DenseMesher.num_threads must be -1 or >= 1, got ",
                  num_threads);
  }
}

namespace {

class Stopwatch {
 public:
  double Lap() {
    const auto now = std::chrono::steady_clock::now();
    const double seconds = std::chrono::duration<double>(now - start_).count();
    start_ = now;
    return seconds;
  }

 private:
  std::chrono::steady_clock::time_point start_ =
      std::chrono::steady_clock::now();
};

// Serialises progress calls from parallel loops and counts completions.
class ProgressCounter {
 public:
  ProgressCounter(const DenseProgress& progress, std::string stage,
                  size_t total)
      : progress_(progress), stage_(std::move(stage)), total_(total) {}
  void Done() {
    std::lock_guard<std::mutex> lock(mutex_);
    ++done_;
    if (progress_) {
      progress_(stage_, done_, total_);
    }
  }

 private:
  const DenseProgress& progress_;
  std::string stage_;
  size_t total_;
  size_t done_ = 0;
  std::mutex mutex_;
};

// OpenCV's own threads would compete with ours on every core; off while we
// run, restored afterwards.
class OpenCvSingleThreaded {
 public:
  OpenCvSingleThreaded() : previous_(cv::getNumThreads()) {
    cv::setNumThreads(1);
  }
  ~OpenCvSingleThreaded() { cv::setNumThreads(previous_); }

 private:
  int previous_;
};

}  // namespace

DenseMeshResult DenseMesh(const Reconstruction& model,
                          const std::filesystem::path& image_dir,
                          const std::filesystem::path& work_dir,
                          DenseMesherOptions options,
                          const DenseProgress& progress) {
  options.Check();
  const std::vector<Image>& images = model.Images();
  DenseMeshResult result;
  result.num_images = images.size();
  if (images.size() < 2) {
    throw ErrorAt("dense mesher: the model has ", images.size(),
                  " image(s); at least 2 are needed");
  }
  const size_t num_threads =
      options.num_threads > 0
          ? static_cast<size_t>(options.num_threads)
          : tbb::global_control::active_value(
                tbb::global_control::max_allowed_parallelism);
  const tbb::global_control parallelism(
      tbb::global_control::max_allowed_parallelism, num_threads);
  const OpenCvSingleThreaded opencv_single_threaded;
  Stopwatch stopwatch;

  const std::vector<ViewNeighbors> selection =
      SelectViews(model, options.view_selection);
  std::vector<PinholeView> views(images.size());
  {
    ProgressCounter counter(progress, "images", images.size());
    tbb::parallel_for(size_t{0}, images.size(), [&](size_t i) {
      const Image& image = images[i];
      const Camera* camera = model.FindCamera(image.camera_id);
      if (camera == nullptr) {
        throw ErrorAt("image ", image.name, ": camera ", image.camera_id,
                      " is not in the model");
      }
      const std::filesystem::path path = image_dir / image.name;
      const cv::Mat pixels = cv::imread(path.string(), cv::IMREAD_UNCHANGED);
      if (pixels.empty()) {
        throw ErrorAt(path.string(), ": missing or unreadable image");
      }
      const double longest =
          static_cast<double>(std::max(camera->width, camera->height));
      const double scale =
          options.max_image_size < 0
              ? 1.0
              : std::min(1.0, options.max_image_size / longest);
      views[i] = MakePinholeView(*camera, image.cam_from_world, pixels, scale,
                                 path.string());
      counter.Done();
    });
  }
  result.seconds["images"] = stopwatch.Lap();

  std::vector<size_t> references;
  for (size_t i = 0; i < images.size(); ++i) {
    if (selection[i].depth_range && !selection[i].neighbors.empty()) {
      references.push_back(i);
    }
  }
  result.num_depth_maps = references.size();
  if (references.size() < 2) {
    throw ErrorAt("dense mesher: only ", references.size(),
                  " image(s) have an overlapping neighbour and 3D points; is "
                  "the model sparse or disconnected?");
  }

  std::vector<cv::Mat> depth_maps(images.size());
  {
    ProgressCounter counter(progress, "depth maps", references.size());
    tbb::parallel_for(
        size_t{0}, references.size(),
        [&](size_t k) {
          const size_t i = references[k];
          std::vector<const PinholeView*> sources;
          for (const size_t j : selection[i].neighbors) {
            sources.push_back(&views[j]);
          }
          depth_maps[i] = PlaneSweepDepth(views[i], sources,
                                          selection[i].depth_range->first,
                                          selection[i].depth_range->second,
                                          options.plane_sweep)
                              .depth;
          counter.Done();
        },
        tbb::simple_partitioner());
  }
  for (size_t i = 0; i < images.size(); ++i) {
    if (depth_maps[i].empty()) {
      depth_maps[i] = cv::Mat::zeros(views[i].grey.size(), CV_32F);
    }
  }
  result.seconds["depth maps"] = stopwatch.Lap();

  // Voxel size from the depth maps' resolution on the surface.
  if (!(options.fusion.voxel_size > 0.0)) {
    std::vector<double> sample_distances;
    for (const size_t i : references) {
      const auto [near, far] = *selection[i].depth_range;
      sample_distances.push_back(0.5 * (near + far) / views[i].K(0, 0));
    }
    std::nth_element(sample_distances.begin(),
                     sample_distances.begin() + sample_distances.size() / 2,
                     sample_distances.end());
    options.fusion.voxel_size = options.voxel_size_factor *
                                sample_distances[sample_distances.size() / 2];
  }
  options.fusion.Check();
  result.voxel_size = options.fusion.voxel_size;

  std::vector<cv::Mat> consistent(images.size());
  {
    ProgressCounter counter(progress, "consistency", images.size());
    tbb::parallel_for(size_t{0}, images.size(), [&](size_t i) {
      consistent[i] = ConsistentDepth(i, selection[i].neighbors, views,
                                      depth_maps, options.fusion);
      counter.Done();
    });
  }
  depth_maps.clear();
  result.points = FuseDepthMaps(views, consistent, options.fusion);
  result.seconds["fusion"] = stopwatch.Lap();
  if (progress) {
    progress("fusion", result.points.points.size(),
             result.points.points.size());
  }

  if (options.poisson.depth <= 0) {
    Eigen::AlignedBox3d box;
    for (const Eigen::Vector3d& point : result.points.points) {
      box.extend(point);
    }
    const double extent = box.isEmpty() ? 0.0 : box.sizes().maxCoeff();
    options.poisson.depth = std::clamp(
        static_cast<int>(
            std::ceil(std::log2(std::max(extent, options.fusion.voxel_size) /
                                options.fusion.voxel_size))),
        6, 12);
  }
  if (options.poisson.num_threads == -1 && options.num_threads > 0) {
    options.poisson.num_threads = options.num_threads;
  }
  result.poisson_depth = options.poisson.depth;
  const TriangleMesh surface =
      PoissonSurface(result.points, options.poisson, work_dir,
                     &result.poisson_non_finite_vertices);
  result.seconds["poisson"] = stopwatch.Lap();

  if (!(options.trimming.max_distance > 0.0)) {
    options.trimming.max_distance = 2.0 * options.fusion.voxel_size;
  }
  result.mesh =
      TrimUnsupported(surface, result.points.points, options.trimming);
  result.seconds["trimming"] = stopwatch.Lap();
  if (result.mesh.triangles.empty()) {
    throw Error(
        "dense mesher: no triangle is supported by the fused points; try a "
        "larger --Trimming.max_distance");
  }
  return result;
}

}  // namespace uw
