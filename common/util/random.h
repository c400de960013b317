// SplitMix64 (Steele, Lea & Flood 2014): the one source of randomness of
// uwsim and of laserscale's Monte Carlo. Its integer arithmetic gives the same
// numbers on every platform and compiler (std distributions do not), and as a
// pure function of a key it serves counter-based generators whose results do
// not depend on how work is split between threads.
#pragma once

#include <cmath>
#include <cstdint>

#include <Eigen/Core>

namespace uw {

inline constexpr uint64_t kSplitMix64Gamma = 0x9E3779B97F4A7C15ull;

// SplitMix64's step and output function: a bijection of x + gamma that
// mixes every input bit into every output bit.
inline uint64_t SplitMix64(uint64_t x) {
  x += kSplitMix64Gamma;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

// The sequential generator: SplitMix64 of seed, seed + gamma, ...
class SplitMix64Stream {
 public:
  explicit SplitMix64Stream(uint64_t seed) : state_(seed) {}

  uint64_t Next() {
    const uint64_t value = SplitMix64(state_);
    state_ += kSplitMix64Gamma;
    return value;
  }
  // Uniform in [0, 1) with 53 random bits.
  double Uniform() { return static_cast<double>(Next() >> 11) * 0x1.0p-53; }
  double Uniform(double low, double high) {
    return low + (high - low) * Uniform();
  }
  // Standard normal by Box-Muller (one of the pair; 1 - u keeps log finite).
  double Gaussian() {
    const double radius = std::sqrt(-2.0 * std::log(1.0 - Uniform()));
    return radius * std::cos(6.283185307179586 * Uniform());
  }
  // Two independent standard normals by Box-Muller (both of the pair): half
  // the cost per number of Gaussian(), for the Monte Carlo's inner loops.
  Eigen::Vector2d GaussianPair() {
    const double radius = std::sqrt(-2.0 * std::log(1.0 - Uniform()));
    const double angle = 6.283185307179586 * Uniform();
    return {radius * std::cos(angle), radius * std::sin(angle)};
  }

 private:
  uint64_t state_;
};

}  // namespace uw
