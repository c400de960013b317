// One timed run of colmap's bundle_adjuster and of ours on a model, with
// the solver's own time and iterations read from their reports. Shared by
// ba_speed_bench.cc (the survey colmap reconstructed) and
// covariance_speed_bench.cc (large observed surveys).
#pragma once

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
};

inline std::string ReadText(const std::filesystem::path& path) {
  std::ifstream stream(path);
  std::ostringstream text;
  text << stream.rdbuf();
  return text.str();
}

// colmap's "Bundle adjustment report": "Iterations : N", "Time : S [s]".
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
          std::regex(R"(Iterations : (\d+)\s+Time : ([0-9.e+-]+))"))) {
    throw std::runtime_error("no report in " + (dir / "log.txt").string());
  }
  run.iterations = std::stoi(match[1]);
  run.solve_s = std::stod(match[2]);
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
  return run;
}

}  // namespace uw::bench
