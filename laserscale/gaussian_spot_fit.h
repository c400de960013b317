// LSD steps 10-11: an elliptical Gaussian on a constant fitted to a spot's
// pixels by Levenberg-Marquardt, with the auxiliary image's print of the
// spot where it overlaps, and clipped pixels as bounds (censored least
// squares).
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "laserscale/spot_levels.h"

namespace uw::lsd {

// An elliptical Gaussian amplitude * exp(-1/2 (x - mean)^T cov^-1 (x - mean))
// in ROI pixel coordinates (COLMAP convention, origin at the ROI's corner).
struct GaussianSpot {
  double amplitude = 0.0;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Identity();
};

// Pixels to fit: centres, signal and whether each value is exact (0), a
// lower bound (1: clipped in the frame it adds) or an upper bound (-1).
// A bound costs nothing while the model respects it (censored least
// squares), so a clipped top still tells how high the spot is.
struct FitSamples {
  std::vector<Eigen::Vector2d> xs;
  std::vector<double> ys;
  std::vector<int8_t> bounds;
};

// Where the aux's print of a spot lies: the aux sees the spot at nearly
// the same image pixel (the lasers move with the camera), which the
// alignment maps to centre + offset in the ROI; the range changed a little
// between the frames, which moves it along the beam's image by some s.
struct PrintGeometry {
  Eigen::Vector2d offset = Eigen::Vector2d::Zero();
  Eigen::Vector2d along = Eigen::Vector2d::UnitX();  // unit
};

// The model B + a exp(-q(x - mu) / 2) [+ a' exp(-q(x - mu') / 2)],
// q(d) = d^T P d, of the spot [and the aux's print, mu' = mu + offset +
// s along] on a constant, with parameters [B, P_11, P_12, P_22, a, mu_x,
// mu_y [, a', s]]; and its Levenberg-Marquardt fit. The spot and its print
// share a shape (one beam on one surface, seen from nearly one place) and
// the print's place follows the spot's up to s: that keeps the pair
// determined when they overlap. Fixed sizes keep the normal equations on
// the stack.
template <bool kWithPrint>
struct SpotFit {
  static constexpr int kParams = kWithPrint ? 9 : 7;
  using Vector = Eigen::Matrix<double, kParams, 1>;
  using Matrix = Eigen::Matrix<double, kParams, kParams>;

  PrintGeometry geometry;

  // The print's centre at theta.
  Eigen::Vector2d PrintMean(const Vector& theta) const {
    return theta.template segment<2>(5) + geometry.offset +
           theta(kParams - 1) * geometry.along;
  }

  double Value(const Vector& theta, const Eigen::Vector2d& x,
               Vector* jacobian) const {
    Eigen::Matrix2d precision;
    precision << theta(1), theta(2), theta(2), theta(3);
    double value = theta(0);
    jacobian->template head<4>() << 1.0, 0.0, 0.0, 0.0;
    // a exp(-q(x - mean) / 2), adding its derivatives by the shape; returns
    // a g P (x - mean), its derivative by the mean.
    const auto add = [&](double a, const Eigen::Vector2d& mean, double* g_out) {
      const Eigen::Vector2d d = x - mean;
      const Eigen::Vector2d pd = precision * d;
      const double q = d.dot(pd);
      // Single precision is ample for the model and twice as fast; the fit
      // spends most of its time here.
      const double g = q < 80.0 ? std::exp(static_cast<float>(-0.5 * q)) : 0.0;
      const double ag = a * g;
      value += ag;
      (*jacobian)(1) -= 0.5 * ag * d.x() * d.x();
      (*jacobian)(2) -= ag * d.x() * d.y();
      (*jacobian)(3) -= 0.5 * ag * d.y() * d.y();
      *g_out = g;
      return Eigen::Vector2d(ag * pd);
    };
    double g = 0.0;
    const Eigen::Vector2d by_mean =
        add(theta(4), theta.template segment<2>(5), &g);
    (*jacobian)(4) = g;
    jacobian->template segment<2>(5) = by_mean;
    if constexpr (kWithPrint) {
      const Eigen::Vector2d by_print_mean = add(theta(7), PrintMean(theta), &g);
      (*jacobian)(7) = g;
      jacobian->template segment<2>(5) += by_print_mean;
      (*jacobian)(8) = by_print_mean.dot(geometry.along);
    }
    return value;
  }

  static bool PrecisionPositive(const Vector& theta) {
    return theta.allFinite() && theta(1) > 0.0 &&
           theta(1) * theta(3) - Square(theta(2)) > 0.0;
  }

  // Cost, J^T J and J^T r at theta; false if not finite.
  bool Evaluate(const FitSamples& samples, const Vector& theta, double* cost,
                Matrix* normal, Vector* gradient) const {
    *cost = 0.0;
    normal->setZero();
    gradient->setZero();
    Vector row;
    for (size_t i = 0; i < samples.xs.size(); ++i) {
      const double residual = Value(theta, samples.xs[i], &row) - samples.ys[i];
      if (residual * samples.bounds[i] > 0.0) continue;  // bound respected
      *cost += residual * residual;
      normal->noalias() += row * row.transpose();
      *gradient += residual * row;
    }
    return std::isfinite(*cost);
  }

  // Levenberg-Marquardt from theta; false if the start is not finite. It
  // stops once a step moves the centre by less than 1e-3 px (far below any
  // noise) and the other parameters by less than 1e-4 of themselves, or
  // barely lowers the cost.
  bool Fit(const FitSamples& samples, Vector* theta) const {
    constexpr int kMaxIterations = 50;
    double cost;
    Matrix normal;
    Vector gradient;
    if (!Evaluate(samples, *theta, &cost, &normal, &gradient)) return false;
    double lambda = 1e-3;
    for (int iteration = 0; iteration < kMaxIterations; ++iteration) {
      while (true) {
        Matrix damped = normal;
        damped.diagonal() += lambda * normal.diagonal().cwiseMax(1e-12);
        const Vector step = damped.ldlt().solve(-gradient);
        bool small = step.template segment<2>(5).norm() < 1e-3;
        for (int k = 1; k < kParams && small; ++k) {
          if (k != 5 && k != 6) {
            small = std::abs(step(k)) <= 1e-4 * std::abs((*theta)(k));
          }
        }
        const Vector candidate = *theta + step;
        double candidate_cost;
        Matrix candidate_normal;
        Vector candidate_gradient;
        if (PrecisionPositive(candidate) &&
            Evaluate(samples, candidate, &candidate_cost, &candidate_normal,
                     &candidate_gradient) &&
            candidate_cost < cost) {
          const double decrease = cost - candidate_cost;
          *theta = candidate;
          cost = candidate_cost;
          normal = candidate_normal;
          gradient = candidate_gradient;
          lambda = std::max(lambda * 0.1, 1e-9);
          if (small || decrease <= 1e-7 * cost) return true;
          break;
        }
        if (small || lambda > 1e10) return true;
        lambda *= 10.0;
      }
    }
    return true;
  }
};

// Fits the spot (and its print, if given, placed by `geometry`) to the
// samples from `start` and `print`; false if the fit failed.
bool FitSpot(const FitSamples& samples, double background,
             const GaussianSpot& start, const PrintGeometry& geometry,
             GaussianSpot* spot, GaussianSpot* print);

// Adds the pixels under `window` to the fit samples: where `lower` is set
// the signal is only a lower bound of the truth (the frame it adds is
// clipped), where `upper` is set an upper bound (the frame it subtracts is
// clipped); where both, nothing is known. Either may be empty (none).
void AddSamples(const cv::Mat& window, const cv::Mat& signal,
                const cv::Mat& lower, const cv::Mat& upper,
                FitSamples* samples);

}  // namespace uw::lsd
