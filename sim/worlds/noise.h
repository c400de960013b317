// Smooth random functions of space, the material of every world's relief:
// Perlin's gradient noise on a hashed lattice and fractal sums of it (fBm).
// Integer hashing and SplitMix64 make them the same bits on every platform
// for the same seed.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "common/util/random.h"

namespace uw::sim {

// 3t^2 - 2t^3 of t clamped to [0, 1]: 0 below, 1 above, C1 in between.
double SmoothStep01(double t);

// Perlin's improved gradient noise (2002) on a hashed lattice: C2 smooth,
// zero mean, unit variance after kGradientNoiseStdDev.
class GradientNoise {
 public:
  explicit GradientNoise(uint64_t seed);

  double operator()(const Eigen::Vector3d& p) const;

 private:
  uint32_t seed_;
};

// Fractal Brownian motion of unit variance: octaves from `wavelength` down
// to `min_wavelength` (at least one), each half the wavelength and
// amplitude of the previous one and randomly shifted.
class Fbm {
 public:
  Fbm(SplitMix64Stream& random, double wavelength, double min_wavelength);

  double operator()(const Eigen::Vector3d& p) const;

 private:
  struct Octave {
    double frequency;
    double amplitude;
    Eigen::Vector3d shift;
  };
  GradientNoise noise_;
  std::vector<Octave> octaves_;
};

}  // namespace uw::sim
