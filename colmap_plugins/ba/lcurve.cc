#include "colmap_plugins/ba/lcurve.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "common/util/error.h"
#include "common/util/figure.h"
#include "common/util/file.h"

namespace uw {

std::vector<double> LogSpacedWeights(double min, double max, int count) {
  if (!(min > 0.0 && max > min && std::isfinite(max) && count >= 5)) {
    throw ErrorAt(
        "L-curve weights need 0 < min < max and at least 5 steps; "
        "got min ",
        min, ", max ", max, ", ", count, " steps");
  }
  std::vector<double> weights;
  for (int i = 0; i < count; ++i) {
    weights.push_back(std::exp(std::log(min) + (std::log(max) - std::log(min)) *
                                                   i / (count - 1)));
  }
  return weights;
}

namespace {

// Samples of the log-log curve equally spaced in arc length, each with its
// log lambda.
struct ArcSamples {
  std::vector<double> s;
  std::vector<double> theta;  // tangent angle, unwrapped
  double spacing = 0.0;
  std::vector<double> length_at_point;  // arc length at each input point
};

constexpr int kNumArcSamples = 400;
// Smoothing scale of the curvature, as a fraction of the curve's length:
// a corner is a turn visible at the scale of the plot, not the vertex of a
// microscopic wiggle where the curve barely moves (its ends, where one
// objective has reached its floor, are nearly stationary).
constexpr double kSmoothingFraction = 0.05;

ArcSamples SampleByArcLength(const std::vector<double>& s,
                             const std::vector<double>& x,
                             const std::vector<double>& y) {
  ArcSamples samples;
  std::vector<double> length(1, 0.0);
  for (size_t i = 1; i < s.size(); ++i) {
    length.push_back(length.back() +
                     std::hypot(x[i] - x[i - 1], y[i] - y[i - 1]));
  }
  samples.length_at_point = length;
  const double total = length.back();
  samples.spacing = total / (kNumArcSamples - 1);
  std::vector<double> sx;
  std::vector<double> sy;
  size_t segment = 0;
  for (int k = 0; k < kNumArcSamples; ++k) {
    const double l = total * k / (kNumArcSamples - 1);
    while (segment + 2 < length.size() && length[segment + 1] < l) ++segment;
    const double span = length[segment + 1] - length[segment];
    const double t =
        span > 0.0 ? std::clamp((l - length[segment]) / span, 0.0, 1.0) : 0.0;
    samples.s.push_back(s[segment] + t * (s[segment + 1] - s[segment]));
    sx.push_back(x[segment] + t * (x[segment + 1] - x[segment]));
    sy.push_back(y[segment] + t * (y[segment + 1] - y[segment]));
  }
  for (int k = 0; k + 1 < kNumArcSamples; ++k) {
    double theta = std::atan2(sy[k + 1] - sy[k], sx[k + 1] - sx[k]);
    if (k > 0) {
      while (theta - samples.theta.back() > M_PI) theta -= 2.0 * M_PI;
      while (theta - samples.theta.back() < -M_PI) theta += 2.0 * M_PI;
    }
    samples.theta.push_back(theta);
  }
  return samples;
}

}  // namespace

LCurve FindLCurveCorner(std::vector<LCurvePoint> points) {
  if (points.size() < 5) {
    throw ErrorAt("an L-curve needs at least 5 points; got ", points.size());
  }
  std::vector<double> s;
  std::vector<double> x;
  std::vector<double> y;
  for (size_t i = 0; i < points.size(); ++i) {
    const LCurvePoint& p = points[i];
    if (!(p.weight_px_per_m > 0.0 && p.reprojection_ms_px2 > 0.0 &&
          p.navigation_ms_m2 > 0.0 && std::isfinite(p.reprojection_ms_px2) &&
          std::isfinite(p.navigation_ms_m2))) {
      throw ErrorAt("L-curve point ", i, " (lambda ", p.weight_px_per_m,
                    ") has a non-positive or non-finite objective");
    }
    if (i > 0 && !(p.weight_px_per_m > points[i - 1].weight_px_per_m)) {
      throw ErrorAt("L-curve weights must increase");
    }
    s.push_back(std::log(p.weight_px_per_m));
    x.push_back(std::log10(p.reprojection_ms_px2));
    y.push_back(std::log10(p.navigation_ms_m2));
  }
  const ArcSamples samples = SampleByArcLength(s, x, y);
  if (!(samples.spacing > 0.0)) {
    throw ErrorAt(
        "the L-curve is a point: the objectives do not change "
        "with lambda");
  }
  // Tangent angle smoothed by a Gaussian in arc length, then curvature =
  // d theta / d length (positive = turning counter-clockwise, the turn
  // from the curve's descent to its run to the right).
  const int n = static_cast<int>(samples.theta.size());
  const double sigma = kSmoothingFraction * (kNumArcSamples - 1);
  std::vector<double> smooth(n);
  for (int k = 0; k < n; ++k) {
    double sum = 0.0;
    double weight_sum = 0.0;
    for (int j = std::max(0, k - static_cast<int>(4 * sigma));
         j < std::min(n, k + static_cast<int>(4 * sigma) + 1); ++j) {
      const double w = std::exp(-0.5 * std::pow((j - k) / sigma, 2));
      sum += w * samples.theta[j];
      weight_sum += w;
    }
    smooth[k] = sum / weight_sum;
  }
  std::vector<double> curvature(n, 0.0);
  for (int k = 1; k + 1 < n; ++k) {
    curvature[k] = (smooth[k + 1] - smooth[k - 1]) / (2.0 * samples.spacing);
  }
  // Ignore the ends, where the one-sided smoothing window biases the turn.
  const int margin = static_cast<int>(sigma);
  int best = margin;
  for (int k = margin; k < n - margin; ++k) {
    if (curvature[k] > curvature[best]) best = k;
  }
  LCurve curve;
  if (curvature[best] > 0.0) {
    curve.corner_weight_px_per_m =
        std::exp(0.5 * (samples.s[best] + samples.s[best + 1]));
  }
  // Curvature of each input point: that of the arc sample at its length.
  double best_distance = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < points.size(); ++i) {
    const int k = std::clamp(static_cast<int>(std::lround(
                                 samples.length_at_point[i] / samples.spacing)),
                             1, n - 2);
    points[i].curvature = curvature[k];
    if (!curve.corner_weight_px_per_m) continue;
    const double distance = std::abs(
        std::log(points[i].weight_px_per_m / *curve.corner_weight_px_per_m));
    if (distance < best_distance) {
      best_distance = distance;
      curve.corner_index = i;
    }
  }
  for (size_t i = 0; i + 1 < points.size(); ++i) {
    const auto imbalance = [](const LCurvePoint& p) {
      return std::log(p.weight_px_per_m * p.weight_px_per_m *
                      (p.navigation_ms_m2 / 3.0) /
                      (p.reprojection_ms_px2 / 2.0));
    };
    const double g0 = imbalance(points[i]);
    const double g1 = imbalance(points[i + 1]);
    if (g0 <= 0.0 && g1 > 0.0) {
      const double t = -g0 / (g1 - g0);
      curve.balance_weight_px_per_m =
          std::exp((1.0 - t) * std::log(points[i].weight_px_per_m) +
                   t * std::log(points[i + 1].weight_px_per_m));
      break;
    }
  }
  curve.points = std::move(points);
  return curve;
}

LCurve SweepLCurve(
    const NavBundleAdjustmentOptions& options,
    const std::vector<ImagePosePrior>& priors, const SoftRig* rig,
    const std::unordered_map<image_t, double>& image_times,
    const Reconstruction& model, const std::vector<double>& weights,
    const std::function<void(size_t, size_t, const LCurvePoint&)>& progress) {
  if (priors.empty()) {
    throw ErrorAt("an L-curve needs navigation priors");
  }
  Reconstruction current = model;
  std::vector<LCurvePoint> points;
  for (size_t i = 0; i < weights.size(); ++i) {
    NavBundleAdjustmentOptions step = options;
    step.weight_px_per_m = weights[i];
    step.estimate_offset_covariance = false;
    const NavBundleAdjustmentReport report =
        AdjustWithNavigation(step, priors, rig, image_times, &current);
    LCurvePoint point;
    point.weight_px_per_m = weights[i];
    point.reprojection_ms_px2 =
        report.final_terms.at("reprojection").mean_squared;
    point.navigation_ms_m2 =
        report.final_terms.at("navigation_position").mean_squared;
    points.push_back(point);
    if (progress) progress(i + 1, weights.size(), point);
  }
  std::sort(points.begin(), points.end(),
            [](const LCurvePoint& a, const LCurvePoint& b) {
              return a.weight_px_per_m < b.weight_px_per_m;
            });
  return FindLCurveCorner(std::move(points));
}

std::string LCurveJson(const LCurve& curve) {
  nlohmann::json points = nlohmann::json::array();
  for (const LCurvePoint& point : curve.points) {
    points.push_back(
        {{"weight_px_per_m", point.weight_px_per_m},
         {"reprojection_ms_px2", point.reprojection_ms_px2},
         {"navigation_ms_m2", point.navigation_ms_m2},
         {"curvature", point.curvature ? nlohmann::json(*point.curvature)
                                       : nlohmann::json()}});
  }
  const nlohmann::json json = {
      {"format", "uwmetric-lcurve"},
      {"version", 1},
      {"objectives",
       "reprojection_ms_px2 = mean |reprojection residual|^2; "
       "navigation_ms_m2 = mean |camera centre - (prior + offset)|^2"},
      {"corner_weight_px_per_m",
       curve.corner_weight_px_per_m
           ? nlohmann::json(*curve.corner_weight_px_per_m)
           : nlohmann::json()},
      {"balance_weight_px_per_m",
       curve.balance_weight_px_per_m
           ? nlohmann::json(*curve.balance_weight_px_per_m)
           : nlohmann::json()},
      {"noise_weight_px_per_m",
       curve.noise_weight_px_per_m
           ? nlohmann::json(*curve.noise_weight_px_per_m)
           : nlohmann::json()},
      {"points", points}};
  return json.dump(2) + "\n";
}

std::vector<std::filesystem::path> LCurveFigurePaths(
    const std::filesystem::path& folder) {
  return {folder / "lcurve.png", folder / "lcurve_curvature.png"};
}

std::vector<Figure> LCurveFigures(const LCurve& curve) {
  std::vector<double> rho, eta, lambda, curvature;
  for (const LCurvePoint& point : curve.points) {
    rho.push_back(point.reprojection_ms_px2);
    eta.push_back(point.navigation_ms_m2);
    if (point.curvature) {
      lambda.push_back(point.weight_px_per_m);
      curvature.push_back(*point.curvature);
    }
  }
  std::string title = "L-curve, \u03bb (px/m): corner ";
  title += curve.corner_weight_px_per_m
               ? fmt::format("{:.4g}", *curve.corner_weight_px_per_m)
               : "none";
  if (curve.balance_weight_px_per_m) {
    title += fmt::format(", balance {:.4g}", *curve.balance_weight_px_per_m);
  }
  if (curve.noise_weight_px_per_m) {
    title += fmt::format(", noise levels {:.4g}", *curve.noise_weight_px_per_m);
  }
  Figure l_curve(title, "reprojection mean square \u03c1 (px\u00b2)",
                 "navigation mean square \u03b7 (m\u00b2)", 8.0, 6.0);
  l_curve.LogX();
  l_curve.LogY();
  l_curve.Line(rho, eta, Figure::Colour(0), "one \u03bb per point");
  l_curve.Points(rho, eta, Figure::Colour(0));
  if (curve.corner_index) {
    l_curve.Points({rho[*curve.corner_index]}, {eta[*curve.corner_index]},
                   Figure::Colour(3), "largest turn (corner)");
  }
  Figure turn("L-curve curvature against \u03bb", "\u03bb (px/m)", "curvature",
              8.0, 3.5);
  turn.LogX();
  turn.Line(lambda, curvature, Figure::Colour(0));
  if (curve.corner_weight_px_per_m) {
    turn.VerticalLine(*curve.corner_weight_px_per_m, Figure::Colour(3),
                      "corner");
  }
  if (curve.balance_weight_px_per_m) {
    turn.VerticalLine(*curve.balance_weight_px_per_m, Figure::Colour(1),
                      "balance");
  }
  if (curve.noise_weight_px_per_m) {
    turn.VerticalLine(*curve.noise_weight_px_per_m, Figure::Colour(2),
                      "noise levels");
  }
  return {l_curve, turn};
}

}  // namespace uw
