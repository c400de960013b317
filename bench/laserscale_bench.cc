// Speed of laserscale's Monte Carlo (issue 5 asks for 5000 iterations of one
// image with 4 lasers in <= 2 s on 2 cores): a laser image of the vent's
// flank at 3 m with set-up C, 1500 features, every noise source sampled;
// wall time on one thread and on every core, and the speed-up. Writes a
// JSON record for bench/results/.
//
//   laserscale_bench OUT.json
#include <cstdio>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "bench/wall_clock.h"
#include "common/util/file.h"
#include "experiments/laser_experiment.h"
#include "sim/generate.h"
#include "sim/laser.h"
#include "sim/survey.h"
#include "sim/world.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: laserscale_bench OUT.json\n");
    return 2;
  }
  using namespace uw;
  const sim::World world =
      sim::MakeWorld(sim::WorldKind::kVent, sim::WorldOptions(), 1);
  const RayCaster caster(world.mesh);
  const Camera camera = sim::SimConfig::DefaultCamera();
  sim::SurveyOptions survey;
  survey.views_max_angle_deg = 0.0;
  survey.views_target = VentFlankTarget(caster);
  const auto stations =
      sim::PlanSurvey(sim::SurveyKind::kViews, world, camera, survey, 1);
  sim::LaserOptions laser_options;
  laser_options.setup = "C";
  ShotOptions shot_options;
  shot_options.noise = {0.5, 0.5, 0.05, 0.001};
  const SyntheticShot shot =
      MakeSyntheticShot(caster, camera, stations[0].cam_from_world,
                        sim::TrueLaserSetup(laser_options), shot_options, 1);
  if (!shot.localized) {
    std::fprintf(stderr, "laserscale_bench: %s\n", shot.problem.c_str());
    return 1;
  }
  const unsigned cores = std::thread::hardware_concurrency();
  nlohmann::json runs = nlohmann::json::array();
  double one_thread = 0.0;
  for (const unsigned threads : {1u, cores}) {
    MonteCarloOptions options;
    options.num_threads = static_cast<int>(threads);
    const double start = uw::bench::WallSeconds();
    const ImageScaleResult result = EstimateImageScale(
        shot.image, 0, shot.calibration, caster, ScaleMethod::kFum, options);
    const double wall = uw::bench::WallSeconds() - start;
    if (threads == 1) one_thread = wall;
    std::printf(
        "[laserscale_bench] %d iterations, %u thread(s): %.3f s (scale %.5f "
        "+- %.5f)\n",
        options.num_iterations, threads, wall, result.monte_carlo.mean,
        result.monte_carlo.std_dev);
    runs.push_back({{"threads", threads},
                    {"iterations", options.num_iterations},
                    {"wall_s", wall},
                    {"speed_up", one_thread / wall}});
  }
  const nlohmann::json record = {
      {"benchmark", "laserscale Monte Carlo, one image, 4 lasers (FUM)"},
      {"features", shot.image.matches.size()},
      {"cores", cores},
      {"runs", runs}};
  WriteFilesAtomically(
      {{argv[1],
        [&](std::ostream& stream) { stream << record.dump(2) << "\n"; }}},
      false);
  return 0;
}
