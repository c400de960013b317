#include "colmap_plugins/align/track_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "common/util/error.h"

namespace uw {

TrackAxis TrackAxisFromCentres(const std::vector<Eigen::Vector3d>& centres) {
  if (centres.size() < 2) {
    throw ErrorAt("track: ", centres.size(),
                  " camera centres; an along-track axis needs at least 2");
  }
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& centre : centres) mean += centre;
  mean /= static_cast<double>(centres.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& centre : centres) {
    scatter += (centre - mean) * (centre - mean).transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter);
  if (!(solver.eigenvalues()(2) > 0.0)) {
    throw ErrorAt("track: all ", centres.size(),
                  " camera centres coincide; no along-track axis");
  }
  TrackAxis axis;
  axis.direction = solver.eigenvectors().col(2).normalized();
  if (axis.direction.dot(centres.back() - centres.front()) < 0.0) {
    axis.direction = -axis.direction;
  }
  double min = std::numeric_limits<double>::infinity();
  double max = -min;
  for (const Eigen::Vector3d& centre : centres) {
    const double x = axis.direction.dot(centre - mean);
    min = std::min(min, x);
    max = std::max(max, x);
  }
  axis.origin = mean + 0.5 * (min + max) * axis.direction;
  axis.length = max - min;
  const double n = static_cast<double>(centres.size());
  axis.rms_along = std::sqrt(solver.eigenvalues()(2) / n);
  axis.rms_across = std::sqrt(std::max(0.0, solver.eigenvalues()(1)) / n);
  return axis;
}

std::optional<std::string> DescribeOneLineTrack(
    const std::vector<Eigen::Vector3d>& centres) {
  if (centres.size() < 3) return std::nullopt;
  const TrackAxis track = TrackAxisFromCentres(centres);
  if (!(track.rms_across < kMinAcrossAlongSpread * track.rms_along)) {
    return std::nullopt;
  }
  return fmt::format(
      "{} camera centres lie nearly on one line (RMS {:.3g} m across it, "
      "{:.3g} m along, axis [{:.2f}, {:.2f}, {:.2f}]): positions alone fix "
      "the model's rotation about the line only through that scatter, so "
      "that rotation (and the position of everything off the line) can be "
      "several of its sigmas off; shape and scale are not affected",
      centres.size(), track.rms_across, track.rms_along, track.direction.x(),
      track.direction.y(), track.direction.z());
}

namespace {

int SegmentOf(double x, double begin, double end, int num_segments) {
  const int segment =
      static_cast<int>(std::floor((x - begin) / (end - begin) * num_segments));
  return std::clamp(segment, 0, num_segments - 1);
}

}  // namespace

std::vector<SegmentScale> PerSegmentScale(
    const std::vector<Eigen::Vector3d>& track,
    const std::vector<Eigen::Vector3d>& reference,
    const std::vector<Eigen::Vector3d>& track_views,
    const std::vector<Eigen::Vector3d>& reference_views, const TrackAxis& axis,
    int num_segments) {
  const size_t n = track.size();
  if (reference.size() != n || track_views.size() != reference_views.size() ||
      (!track_views.empty() && track_views.size() != n)) {
    throw ErrorAt("per-segment scale: ", n, " centres, ", reference.size(),
                  " reference centres, ", track_views.size(), " and ",
                  reference_views.size(), " viewing directions");
  }
  if (num_segments < 1) {
    throw ErrorAt("per-segment scale: num_segments must be >= 1, got ",
                  num_segments);
  }
  const double begin = -0.5 * axis.length;
  const double end = 0.5 * axis.length;
  std::vector<SegmentScale> segments(num_segments);
  std::vector<double> reference_3d(num_segments, 0.0);
  std::vector<double> track_3d(num_segments, 0.0);
  std::vector<double> reference_along(num_segments, 0.0);
  std::vector<double> track_along(num_segments, 0.0);
  for (int s = 0; s < num_segments; ++s) {
    segments[s].begin = begin + (end - begin) * s / num_segments;
    segments[s].end = begin + (end - begin) * (s + 1) / num_segments;
  }
  for (size_t k = 0; k + 1 < n; ++k) {
    const int s =
        SegmentOf(axis.AlongTrack(0.5 * (reference[k] + reference[k + 1])),
                  begin, end, num_segments);
    const Eigen::Vector3d reference_step = reference[k + 1] - reference[k];
    const Eigen::Vector3d track_step = track[k + 1] - track[k];
    ++segments[s].num_steps;
    reference_3d[s] += reference_step.norm();
    track_3d[s] += track_step.norm();
    reference_along[s] += std::abs(axis.direction.dot(reference_step));
    track_along[s] += std::abs(axis.direction.dot(track_step));
  }
  Eigen::Vector3d mean_view = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& view : reference_views) mean_view += view;
  const Eigen::Vector3d tilt_axis =
      axis.direction.cross(mean_view).normalized();
  std::vector<double> tilt_sum(num_segments, 0.0);
  for (size_t k = 0; k < n; ++k) {
    const int s =
        SegmentOf(axis.AlongTrack(reference[k]), begin, end, num_segments);
    ++segments[s].num_images;
    if (track_views.empty() || !tilt_axis.allFinite()) continue;
    const Eigen::Vector3d& from = reference_views[k];
    const Eigen::Vector3d& to = track_views[k];
    tilt_sum[s] += std::atan2(from.cross(to).dot(tilt_axis), from.dot(to));
  }
  for (int s = 0; s < num_segments; ++s) {
    SegmentScale& segment = segments[s];
    if (track_3d[s] > 0.0) segment.scale_3d = reference_3d[s] / track_3d[s];
    if (track_along[s] > 0.0) {
      segment.scale_along_track = reference_along[s] / track_along[s];
    }
    if (segment.num_images > 0) {
      segment.view_tilt_deg = tilt_sum[s] / segment.num_images * 180.0 / M_PI;
    }
  }
  return segments;
}

std::vector<DeviationBin> BinAlongTrack(const std::vector<double>& along_track,
                                        const std::vector<double>& values,
                                        double begin, double end,
                                        int num_bins) {
  if (along_track.size() != values.size() || num_bins < 1 || !(end > begin)) {
    throw ErrorAt("along-track bins: ", along_track.size(), " positions, ",
                  values.size(), " values, ", num_bins, " bins over [", begin,
                  ", ", end, ")");
  }
  std::vector<std::vector<double>> binned(num_bins);
  for (size_t i = 0; i < values.size(); ++i) {
    const double x = along_track[i];
    if (!(x >= begin && x < end)) continue;
    binned[SegmentOf(x, begin, end, num_bins)].push_back(values[i]);
  }
  std::vector<DeviationBin> bins(num_bins);
  for (int b = 0; b < num_bins; ++b) {
    bins[b].begin = begin + (end - begin) * b / num_bins;
    bins[b].end = begin + (end - begin) * (b + 1) / num_bins;
    bins[b].count = binned[b].size();
    bins[b].median_m = Quantile(binned[b], 0.5);
  }
  return bins;
}

DomeFit FitDome(const std::vector<DeviationBin>& bins, double track_length,
                size_t min_count) {
  std::vector<double> xs;
  std::vector<double> ds;
  for (const DeviationBin& bin : bins) {
    if (bin.count < std::max<size_t>(min_count, 1)) continue;
    xs.push_back(0.5 * (bin.begin + bin.end));
    ds.push_back(bin.median_m);
  }
  DomeFit fit;
  fit.num_bins_used = xs.size();
  if (xs.size() < 3 || !(track_length > 0.0)) return fit;
  Eigen::MatrixXd design(xs.size(), 3);
  Eigen::VectorXd rhs(xs.size());
  for (size_t i = 0; i < xs.size(); ++i) {
    design.row(i) << 1.0, xs[i], xs[i] * xs[i];
    rhs(i) = ds[i];
  }
  const Eigen::Vector3d c = design.colPivHouseholderQr().solve(rhs);
  fit.valid = true;
  fit.coefficients = {c(0), c(1), c(2)};
  fit.sagitta_m = c(2) * track_length * track_length / 4.0;
  fit.sagitta_percent = 100.0 * fit.sagitta_m / track_length;
  return fit;
}

DistanceRatios CameraDistanceRatios(const std::vector<Eigen::Vector3d>& a,
                                    const std::vector<Eigen::Vector3d>& b,
                                    double min_distance_fraction,
                                    size_t max_images) {
  if (a.size() != b.size()) {
    throw ErrorAt("camera distance ratios: ", a.size(), " and ", b.size(),
                  " centres");
  }
  std::vector<size_t> subset;
  const size_t n = a.size();
  const size_t m = std::min(n, std::max<size_t>(max_images, 2));
  for (size_t k = 0; k < m; ++k) {
    subset.push_back(m > 1 ? k * (n - 1) / (m - 1) : k);
  }
  double max_reference = 0.0;
  for (size_t i = 0; i < subset.size(); ++i) {
    for (size_t j = i + 1; j < subset.size(); ++j) {
      max_reference =
          std::max(max_reference, (b[subset[i]] - b[subset[j]]).norm());
    }
  }
  std::vector<double> ratios;
  for (size_t i = 0; i < subset.size(); ++i) {
    for (size_t j = i + 1; j < subset.size(); ++j) {
      const double reference = (b[subset[i]] - b[subset[j]]).norm();
      if (!(reference > 0.0) ||
          reference < min_distance_fraction * max_reference) {
        continue;
      }
      ratios.push_back((a[subset[i]] - a[subset[j]]).norm() / reference);
    }
  }
  DistanceRatios result;
  result.num_pairs = ratios.size();
  if (ratios.empty()) return result;
  result.median_ratio = Quantile(ratios, 0.5);
  std::vector<double> deviations;
  for (const double ratio : ratios) deviations.push_back(std::abs(ratio - 1.0));
  result.max_abs_deviation =
      *std::max_element(deviations.begin(), deviations.end());
  result.p95_abs_deviation = Quantile(deviations, 0.95);
  return result;
}

double Quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const double position = std::clamp(q, 0.0, 1.0) * (values.size() - 1);
  const size_t lower = static_cast<size_t>(std::floor(position));
  const size_t upper = std::min(lower + 1, values.size() - 1);
  return values[lower] + (position - lower) * (values[upper] - values[lower]);
}

}  // namespace uw
