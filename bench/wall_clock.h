// Clocks for the benchmarks.
#pragma once

#include <chrono>
#include <ctime>

namespace uw::bench {

// Wall-clock seconds (steady, not adjusted).
inline double WallSeconds() {
  return std::chrono::duration<double>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

// Process CPU time: with other work on the machine, wall time measures
// the machine's load as much as the code under test.
inline double CpuSeconds() {
  timespec time;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &time);
  return static_cast<double>(time.tv_sec) + 1e-9 * time.tv_nsec;
}

}  // namespace uw::bench
