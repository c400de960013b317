// Runs another program as a benchmark measures it: wall time, CPU time of
// the process and its threads, and its peak resident memory (the kernel's
// ru_maxrss of the waited-for child). Shared by the benchmarks that time
// our programs against colmap's or Ceres' (ba_speed_bench.cc,
// covariance_speed_bench.cc).
#pragma once

#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

extern char** environ;

namespace uw::bench {

struct ProcessTimes {
  double wall_s = 0.0;
  double cpu_s = 0.0;  // user + system of the process and its threads
  double max_rss_mb = 0.0;
  int exit_code = 0;
};

// Runs argv (looked up on PATH) with stdout and stderr into `log`. Throws
// when it cannot start, or when it fails and !allow_failure.
inline ProcessTimes RunTimed(const std::vector<std::string>& argv,
                             const std::filesystem::path& log,
                             bool allow_failure = false) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  std::vector<char*> args;
  for (const std::string& arg : argv)
    args.push_back(const_cast<char*>(arg.c_str()));
  args.push_back(nullptr);
  const auto start = std::chrono::steady_clock::now();
  pid_t pid = 0;
  const int error =
      posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (error != 0) throw std::runtime_error("cannot start " + argv[0]);
  int status = 0;
  rusage usage{};
  wait4(pid, &status, 0, &usage);
  ProcessTimes times;
  times.wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  times.cpu_s = usage.ru_utime.tv_sec + 1e-6 * usage.ru_utime.tv_usec +
                usage.ru_stime.tv_sec + 1e-6 * usage.ru_stime.tv_usec;
  times.max_rss_mb = usage.ru_maxrss / 1024.0;  // kilobytes on Linux
  times.exit_code =
      WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  if (times.exit_code != 0 && !allow_failure) {
    throw std::runtime_error(argv[0] + " failed; see " + log.string());
  }
  return times;
}

// The machine's 1-minute load average: a benchmark's record says how busy
// the machine was besides.
inline double LoadAverage1Min() {
  std::ifstream file("/proc/loadavg");
  double load = 0.0;
  file >> load;
  return load;
}

}  // namespace uw::bench
