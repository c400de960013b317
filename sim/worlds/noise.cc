#include "sim/worlds/noise.h"

#include <algorithm>
#include <cmath>

namespace uw::sim {
namespace {

// Wellons' "lowbias32" mix; nested per axis it hashes lattice cells with no
// period shorter than 2^32 cells.
uint32_t Avalanche(uint32_t h) {
  h ^= h >> 16;
  h *= 0x7feb352du;
  h ^= h >> 15;
  h *= 0x846ca68bu;
  h ^= h >> 16;
  return h;
}

double Fade(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }

// Standard deviation of the raw noise over random points in 3D, measured
// over 2 * 10^6 of them (0.27; 0.25 on a lattice plane).
constexpr double kGradientNoiseStdDev = 0.27;

// Dot product with one of Perlin's 12 cube-edge gradients (four repeated
// to make 16).
double Gradient(uint32_t hash, double x, double y, double z) {
  switch (hash >> 28) {
    case 0:
    case 12:
      return x + y;
    case 1:
    case 13:
      return -x + y;
    case 2:
      return x - y;
    case 3:
      return -x - y;
    case 4:
      return x + z;
    case 5:
      return -x + z;
    case 6:
      return x - z;
    case 7:
      return -x - z;
    case 8:
      return y + z;
    case 9:
    case 14:
      return -y + z;
    case 10:
      return y - z;
    default:
      return -y - z;
  }
}

}  // namespace

double SmoothStep01(double t) {
  t = std::clamp(t, 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

GradientNoise::GradientNoise(uint64_t seed)
    : seed_(static_cast<uint32_t>(seed ^ (seed >> 32))) {}

double GradientNoise::operator()(const Eigen::Vector3d& p) const {
  const Eigen::Vector3d cell = p.array().floor();
  const Eigen::Vector3d f = p - cell;
  const uint32_t ix = static_cast<uint32_t>(static_cast<int64_t>(cell.x()));
  const uint32_t iy = static_cast<uint32_t>(static_cast<int64_t>(cell.y()));
  const uint32_t iz = static_cast<uint32_t>(static_cast<int64_t>(cell.z()));
  double corner[2][2][2];
  for (uint32_t i = 0; i < 2; ++i) {
    const uint32_t hx = Avalanche(seed_ + ix + i);
    for (uint32_t j = 0; j < 2; ++j) {
      const uint32_t hxy = Avalanche(hx + iy + j);
      for (uint32_t k = 0; k < 2; ++k) {
        corner[i][j][k] =
            Gradient(Avalanche(hxy + iz + k), f.x() - i, f.y() - j, f.z() - k);
      }
    }
  }
  const double u = Fade(f.x()), v = Fade(f.y()), w = Fade(f.z());
  const auto lerp = [](double a, double b, double t) {
    return a + t * (b - a);
  };
  const double y0 = lerp(lerp(corner[0][0][0], corner[1][0][0], u),
                         lerp(corner[0][1][0], corner[1][1][0], u), v);
  const double y1 = lerp(lerp(corner[0][0][1], corner[1][0][1], u),
                         lerp(corner[0][1][1], corner[1][1][1], u), v);
  return lerp(y0, y1, w) / kGradientNoiseStdDev;
}

Fbm::Fbm(SplitMix64Stream& random, double wavelength, double min_wavelength)
    : noise_(random.Next()) {
  double sum_squares = 0.0;
  for (double lambda = wavelength, amplitude = 1.0;
       octaves_.empty() || lambda >= min_wavelength;
       lambda *= 0.5, amplitude *= 0.5) {
    const Eigen::Vector3d shift(random.Uniform(0.0, 1024.0),
                                random.Uniform(0.0, 1024.0),
                                random.Uniform(0.0, 1024.0));
    octaves_.push_back({1.0 / lambda, amplitude, shift});
    sum_squares += amplitude * amplitude;
  }
  for (Octave& octave : octaves_) octave.amplitude /= std::sqrt(sum_squares);
}

double Fbm::operator()(const Eigen::Vector3d& p) const {
  double sum = 0.0;
  for (const Octave& octave : octaves_) {
    sum += octave.amplitude * noise_(octave.frequency * p + octave.shift);
  }
  return sum;
}

}  // namespace uw::sim
