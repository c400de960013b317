#include "colmap_plugins/dense/plane_sweep.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <opencv2/imgproc.hpp>

#include "common/util/error.h"

namespace uw {

void PlaneSweepOptions::Check() const {
  if (window_radius < 1) {
    throw ErrorAt("PlaneSweep.window_radius must be >= 1, got ", window_radius);
  }
  if (!(plane_step_px > 0.0)) {
    throw ErrorAt("PlaneSweep.plane_step_px must be > 0, got ", plane_step_px);
  }
  if (num_best_sources < 1) {
    throw ErrorAt("PlaneSweep.num_best_sources must be >= 1, got ",
                  num_best_sources);
  }
  if (!(max_cost > 0.0 && max_cost <= 2.0)) {
    throw ErrorAt("PlaneSweep.max_cost must be in (0, 2], got ", max_cost);
  }
  if (!(min_texture >= 0.0)) {
    throw ErrorAt("PlaneSweep.min_texture must be >= 0, got ", min_texture);
  }
}

namespace {

// No source: worse than any NCC cost (which lies in [0, 2]).
constexpr float kInvalidCost = 3.0f;
// What a source that does not see a pixel adds to its aggregated cost.
constexpr float kUnseenCost = 1.0f;

// Into a preallocated `mean`: per-plane buffers are reused, as fresh
// megabyte-sized buffers per plane cost more in page faults than the
// filtering itself.
void BoxMean(const cv::Mat& image, int radius, cv::Mat* mean) {
  cv::boxFilter(image, *mean, CV_32F, cv::Size(2 * radius + 1, 2 * radius + 1),
                cv::Point(-1, -1), true, cv::BORDER_REFLECT);
}

// A source relative to the reference: x_source = R x_ref + t.
struct SourceGeometry {
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  const PinholeView* view;
};

}  // namespace

DepthMap PlaneSweepDepth(const PinholeView& reference,
                         const std::vector<const PinholeView*>& sources,
                         double min_depth, double max_depth,
                         const PlaneSweepOptions& options) {
  options.Check();
  if (sources.empty() || sources.size() > 16) {
    throw ErrorAt("plane sweep needs 1 to 16 source images, got ",
                  sources.size());
  }
  if (!(min_depth > 0.0 && min_depth < max_depth && std::isfinite(max_depth))) {
    throw ErrorAt("plane sweep needs 0 < min_depth < max_depth, got ",
                  min_depth, " and ", max_depth);
  }
  const int width = reference.Width();
  const int height = reference.Height();
  const int r = options.window_radius;

  // Reference statistics, the same for every plane.
  const cv::Mat& ref = reference.grey;
  cv::Mat ref_mean;
  cv::Mat ref_var;
  BoxMean(ref, r, &ref_mean);
  BoxMean(ref.mul(ref), r, &ref_var);
  ref_var -= ref_mean.mul(ref_mean);

  std::vector<SourceGeometry> geometry;
  double max_baseline_px = 0.0;
  const Eigen::Matrix3d ref_R = reference.cam_from_world.RotationMatrix();
  for (const PinholeView* source : sources) {
    SourceGeometry g;
    g.view = source;
    const Eigen::Matrix3d src_R = source->cam_from_world.RotationMatrix();
    g.R = src_R * ref_R.transpose();
    g.t = source->cam_from_world.translation -
          g.R * reference.cam_from_world.translation;
    // A point's image moves by about f * |t_xy| per unit of inverse depth.
    max_baseline_px = std::max(max_baseline_px,
                               source->K(0, 0) * g.t.head<2>().norm() +
                                   source->K(0, 0) * std::abs(g.t.z()) * 0.5);
    geometry.push_back(g);
  }
  const double inv_near = 1.0 / min_depth;
  const double inv_far = 1.0 / max_depth;
  const int num_planes = std::max(
      3, static_cast<int>(std::ceil((inv_near - inv_far) * max_baseline_px /
                                    options.plane_step_px)) +
             1);
  const double inv_step = (inv_near - inv_far) / (num_planes - 1);

  const Eigen::Matrix3d ref_K_inv = reference.K.inverse();
  const size_t num_pixels = static_cast<size_t>(width) * height;
  const int num_sources = static_cast<int>(sources.size());
  const int num_best = std::min(options.num_best_sources, num_sources);
  std::vector<cv::Mat> source_cost(num_sources);
  cv::Mat warped;
  cv::Mat product;
  cv::Mat warped_mean;
  cv::Mat warped_sq;
  cv::Mat cross;
  std::vector<float> previous(num_pixels, kInvalidCost);
  std::vector<float> best(num_pixels, std::numeric_limits<float>::max());
  std::vector<float> best_before(num_pixels, kInvalidCost);
  std::vector<float> best_after(num_pixels, kInvalidCost);
  std::vector<int> best_plane(num_pixels, -1);
  std::vector<float> current(num_pixels);
  std::vector<float> current_valid(num_pixels);
  // Mean cost over the sources that see the pixel, at the best plane.
  std::vector<float> best_valid(num_pixels, kInvalidCost);

  for (int plane = 0; plane < num_planes; ++plane) {
    const double inverse_depth = inv_far + plane * inv_step;
    for (int s = 0; s < num_sources; ++s) {
      const SourceGeometry& g = geometry[s];
      // Points of the plane z = 1 / inverse_depth: x_src ~ K_src (R + t n^T
      // inverse_depth) K_ref^-1 u, with n = (0, 0, 1).
      Eigen::Matrix3d plane_map = g.R;
      plane_map.col(2) += g.t * inverse_depth;
      const Eigen::Matrix3d H = g.view->K * plane_map * ref_K_inv;
      cv::Mat H_cv(3, 3, CV_64F);
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
          H_cv.at<double>(i, j) = H(i, j);
        }
      }
      cv::warpPerspective(g.view->grey, warped, H_cv, ref.size(),
                          cv::INTER_LINEAR | cv::WARP_INVERSE_MAP,
                          cv::BORDER_CONSTANT, cv::Scalar(0.0));
      BoxMean(warped, r, &warped_mean);
      cv::multiply(warped, warped, product);
      BoxMean(product, r, &warped_sq);
      cv::multiply(ref, warped, product);
      BoxMean(product, r, &cross);
      cv::Mat& cost = source_cost[s];
      cost.create(height, width, CV_32F);  // allocated at the first plane
      for (int y = 0; y < height; ++y) {
        const float* mr = ref_mean.ptr<float>(y);
        const float* vr = ref_var.ptr<float>(y);
        const float* mw = warped_mean.ptr<float>(y);
        const float* sw = warped_sq.ptr<float>(y);
        const float* c = cross.ptr<float>(y);
        const float* w = warped.ptr<float>(y);
        float* out = cost.ptr<float>(y);
        for (int x = 0; x < width; ++x) {
          const float var_w = sw[x] - mw[x] * mw[x];
          // A warped pixel of exactly 0 lies outside the source image.
          if (w[x] == 0.0f || var_w < 1e-8f || vr[x] < 1e-8f) {
            out[x] = kInvalidCost;
            continue;
          }
          const float ncc = (c[x] - mr[x] * mw[x]) / std::sqrt(vr[x] * var_w);
          out[x] = 1.0f - std::clamp(ncc, -1.0f, 1.0f);
        }
      }
    }
    // Mean of the num_best lowest source costs per pixel, a source that
    // does not see the pixel counting as uncorrelated (1 - NCC = 1): planes
    // that more sources see are preferred, and a pixel only one source sees
    // still gets its best plane.
    std::array<float, 16> costs{};
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        const size_t index = static_cast<size_t>(y) * width + x;
        const int n = std::min(num_sources, 16);
        for (int s = 0; s < n; ++s) {
          costs[s] = source_cost[s].ptr<float>(y)[x];
        }
        std::partial_sort(costs.begin(), costs.begin() + num_best,
                          costs.begin() + n);
        float sum = 0.0f;
        float valid_sum = 0.0f;
        int num_valid = 0;
        for (int k = 0; k < num_best; ++k) {
          if (costs[k] < kInvalidCost) {
            sum += costs[k];
            valid_sum += costs[k];
            ++num_valid;
          } else {
            sum += kUnseenCost;
          }
        }
        current[index] = sum / static_cast<float>(num_best);
        current_valid[index] = num_valid > 0
                                   ? valid_sum / static_cast<float>(num_valid)
                                   : kInvalidCost;
      }
    }
    for (size_t index = 0; index < num_pixels; ++index) {
      if (current[index] < best[index]) {
        best[index] = current[index];
        best_valid[index] = current_valid[index];
        best_plane[index] = plane;
        best_before[index] = previous[index];
        best_after[index] = kInvalidCost;
      } else if (best_plane[index] == plane - 1) {
        best_after[index] = current[index];
      }
    }
    std::swap(previous, current);
  }

  DepthMap result;
  result.num_planes = num_planes;
  result.depth = cv::Mat::zeros(height, width, CV_32F);
  result.cost = cv::Mat::zeros(height, width, CV_32F);
  const float min_var =
      static_cast<float>(options.min_texture * options.min_texture);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const size_t index = static_cast<size_t>(y) * width + x;
      const int plane = best_plane[index];
      // A minimum at the first or last plane is no minimum: the surface
      // may lie beyond the range.
      if (plane <= 0 || plane >= num_planes - 1 ||
          best_valid[index] > options.max_cost ||
          ref_var.at<float>(y, x) < min_var ||
          best_before[index] >= kInvalidCost ||
          best_after[index] >= kInvalidCost) {
        continue;
      }
      // Parabola through the three costs around the minimum.
      const double before = best_before[index];
      const double after = best_after[index];
      const double curvature = before - 2.0 * best[index] + after;
      double offset = 0.0;
      if (curvature > 0.0) {
        offset = std::clamp(0.5 * (before - after) / curvature, -0.5, 0.5);
      }
      const double inverse_depth = inv_far + (plane + offset) * inv_step;
      result.depth.at<float>(y, x) = static_cast<float>(1.0 / inverse_depth);
      result.cost.at<float>(y, x) = best_valid[index];
    }
  }
  return result;
}

}  // namespace uw
