// Rendering speed of uwsim on its default world and survey: Mpixel/s per
// core, on one thread (CPU time) and on every core (wall time), at
// supersampling 1 and 2 (the default), for the default SIMPLE_RADIAL
// 1024x768 camera. Writes a JSON record for bench/results/.
//
//   render_bench OUT.json [--images N]
#include <chrono>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <string>
#include <thread>

#include <tbb/global_control.h>
#include <nlohmann/json.hpp>

#include "bench/wall_clock.h"
#include "common/mesh/ray_caster.h"
#include "common/util/file.h"
#include "sim/generate.h"

namespace {

double CpuSeconds() {
  timespec time;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &time);
  return static_cast<double>(time.tv_sec) + 1e-9 * time.tv_nsec;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: render_bench OUT.json [--images N]\n");
    return 2;
  }
  int num_images = 4;
  if (argc == 4 && std::string(argv[2]) == "--images") {
    num_images = std::stoi(argv[3]);
  }
  using namespace uw::sim;
  const SimConfig config;
  const World world =
      MakeWorld(config.world, config.world_options, config.seed);
  const std::vector<SurveyStation> stations = PlanSurvey(
      config.survey, world, config.camera, config.survey_options, config.seed);
  const uw::RayCaster caster(world.mesh);
  const double pixels =
      static_cast<double>(config.camera.width * config.camera.height);
  const unsigned cores = std::thread::hardware_concurrency();
  nlohmann::json runs = nlohmann::json::array();
  for (const int supersampling : {1, 2}) {
    RenderOptions options = config.render;
    options.sensor.supersampling = supersampling;
    const Renderer renderer(caster, *world.texture, config.camera, options);
    for (const unsigned threads : {1u, cores}) {
      const tbb::global_control limit(
          tbb::global_control::max_allowed_parallelism, threads);
      const double cpu_start = CpuSeconds();
      const double wall_start = uw::bench::WallSeconds();
      for (int i = 0; i < num_images; ++i) {
        renderer.Render(stations[i % stations.size()].cam_from_world,
                        config.seed, i);
      }
      const double cpu = CpuSeconds() - cpu_start;
      const double wall = uw::bench::WallSeconds() - wall_start;
      const double mpixels = num_images * pixels / 1e6;
      const nlohmann::json run = {
          {"supersampling", supersampling},
          {"threads", threads},
          {"images", num_images},
          {"mpixel_per_s_per_core", mpixels / cpu},
          {"mpixel_per_s_wall", mpixels / wall},
          {"parallel_efficiency", cpu / (wall * threads)}};
      std::printf(
          "[render_bench] supersampling %d, %u thread(s): %.2f Mpixel/s per "
          "core (CPU time), %.2f Mpixel/s wall\n",
          supersampling, threads, mpixels / cpu, mpixels / wall);
      runs.push_back(run);
    }
  }
  const nlohmann::json record = {
      {"benchmark", "uwsim rendering, default seafloor/lawnmower"},
      {"camera", "SIMPLE_RADIAL 1024x768"},
      {"triangles", world.mesh.triangles.size()},
      {"cores", cores},
      {"runs", runs}};
  uw::WriteFilesAtomically(
      {{argv[1],
        [&](std::ostream& stream) { stream << record.dump(2) << "\n"; }}},
      false);
  return 0;
}
