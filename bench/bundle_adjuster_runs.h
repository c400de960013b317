// One timed run of colmap's bundle_adjuster and of ours on a model, with
// the solver's own time and iterations read from their reports. Shared by
// ba_speed_bench.cc (the survey colmap reconstructed) and
// covariance_speed_bench.cc (large observed surveys).
#pragma once

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "bench/timed_run.h"

namespace uw::bench {

struct Run {
  ProcessTimes process;
  double solve_s = 0.0;
  int iterations = 0;
  // RMS reprojection error per observation (px), at the input and at the
  // end: a speed ratio means nothing if one stops at a worse optimum.
  double initial_rms_px = 0.0;
  double final_rms_px = 0.0;
};

inline std::string ReadText(const std::filesystem::path& path) {
  std::ifstream stream(path);
  std::ostringstream text;
  text << stream.rdbuf();
  return text.str();
}

// colmap's "Bundle adjustment report": "Iterations : N", "Time : S [s]",
// "Initial cost : C0 [px]", "Final cost : C [px]", where C is
// sqrt(Ceres cost / residuals) = sqrt(0.5 sum |r|^2 / (2 observations)):
// half the RMS error per observation.
inline Run ColmapRun(const std::filesystem::path& input,
                     const std::filesystem::path& dir) {
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  Run run;
  run.process = RunTimed({"colmap", "bundle_adjuster", "--input_path",
                          input.string(), "--output_path", dir.string()},
                         dir / "log.txt");
  const std::string log = ReadText(dir / "log.txt");
  std::smatch match;
  if (!std::regex_search(
          log, match,
          std::regex(R"(Iterations : (\d+)\s+Time : ([0-9.e+-]+) \[s\]\s+)"
                     R"(Initial cost : ([0-9.e+-]+) \[px\]\s+)"
                     R"(Final cost : ([0-9.e+-]+) \[px\])"))) {
    throw std::runtime_error("no report in " + (dir / "log.txt").string());
  }
  run.iterations = std::stoi(match[1]);
  run.solve_s = std::stod(match[2]);
  run.initial_rms_px = 2.0 * std::stod(match[3]);
  run.final_rms_px = 2.0 * std::stod(match[4]);
  return run;
}

inline Run OursRun(const std::string& uwcolmap,
                   const std::filesystem::path& input,
                   const std::filesystem::path& dir, int threads) {
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  Run run;
  run.process = RunTimed(
      {uwcolmap, "bundle_adjuster", "--input_path", input.string(),
       "--output_path", dir.string(), "--num_threads", std::to_string(threads)},
      dir / "log.txt");
  const nlohmann::json report =
      nlohmann::json::parse(ReadText(dir / "ba_report.json"));
  run.iterations = report.at("iterations").get<int>();
  run.solve_s = report.at("solve_time_s").get<double>();
  // Mean squared reprojection error per observation (px^2).
  const auto rms = [&](const char* key) {
    return std::sqrt(
        report.at(key).at("reprojection").at("mean_squared").get<double>());
  };
  run.initial_rms_px = rms("initial_cost");
  run.final_rms_px = rms("final_cost");
  return run;
}

}  // namespace uw::bench
