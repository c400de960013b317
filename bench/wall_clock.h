// Wall-clock seconds for the benchmarks (steady, not adjusted).
#pragma once

#include <chrono>

namespace uw::bench {

inline double WallSeconds() {
  return std::chrono::duration<double>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace uw::bench
