// Speed of the laser-spot detector (issue 5 asks for <= 0.2 s per 1024x768
// image): DetectSpots with its default options (100 Monte Carlo
// iterations) on laser images of uwsim's default survey (seafloor, set-up C,
// 4 lasers, auxiliary images with the lasers "shifted"), 1024x768; wall time
// per image on one thread and on every core, and the speed-up. Writes a JSON
// record for bench/results/.
//
//   spot_detector_bench OUT.json [--images N]
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "bench/wall_clock.h"
#include "common/mesh/ray_caster.h"
#include "common/util/file.h"
#include "laserscale/spot_detector.h"
#include "sim/generate.h"
#include "sim/laser_images.h"

int main(int argc, char** argv) {
  if (argc != 2 && !(argc == 4 && std::string(argv[2]) == "--images")) {
    std::fprintf(stderr, "usage: spot_detector_bench OUT.json [--images N]\n");
    return 2;
  }
  const size_t num_images = argc == 4 ? std::stoul(argv[3]) : 4;
  using namespace uw;
  const sim::SimConfig config;
  const sim::World world =
      sim::MakeWorld(config.world, config.world_options, config.seed);
  const RayCaster caster(world.mesh);
  const std::vector<sim::SurveyStation> stations = sim::PlanSurvey(
      config.survey, world, config.camera, config.survey_options, config.seed);
  const std::vector<sim::LaserShot> shots =
      sim::PlanLaserShots(stations, config.lasers, config.seed);
  const LaserSetup truth = sim::TrueLaserSetup(config.lasers);
  const LaserSetup calibrated =
      sim::CalibratedLaserSetup(truth, config.lasers, config.seed);
  const sim::Renderer renderer(caster, *world.texture, config.camera,
                               config.render);
  sim::FrameOptions lasers_on;
  lasers_on.lasers = truth.lasers;
  lasers_on.optics = config.lasers.optics;
  sim::FrameOptions aux_frame = lasers_on;  // "shifted": lasers on
  aux_frame.gain_factor = config.lasers.aux_gain;

  struct Images {
    cv::Mat image;
    cv::Mat aux;
  };
  std::vector<Images> images;
  for (size_t i = 0; i < std::min(num_images, shots.size()); ++i) {
    images.push_back(
        {renderer.Render(shots[i].cam_from_world, config.seed, 2 * i, lasers_on)
             .image,
         renderer
             .Render(shots[i].aux_cam_from_world, config.seed, 2 * i + 1,
                     aux_frame)
             .image});
  }

  const unsigned cores = std::thread::hardware_concurrency();
  nlohmann::json runs = nlohmann::json::array();
  double one_thread = 0.0;
  for (const unsigned threads : {1u, cores}) {
    SpotDetectorOptions options;
    options.num_threads = static_cast<int>(threads);
    int stable = 0;
    const double start = uw::bench::WallSeconds();
    const double cpu_start = uw::bench::CpuSeconds();
    for (size_t i = 0; i < images.size(); ++i) {
      for (const DetectedSpot& spot :
           DetectSpots(images[i].image, images[i].aux, config.camera,
                       calibrated, options, i)) {
        stable += spot.stable ? 1 : 0;
      }
    }
    const double per_image = (uw::bench::WallSeconds() - start) / images.size();
    const double cpu_per_image =
        (uw::bench::CpuSeconds() - cpu_start) / images.size();
    if (threads == 1) one_thread = per_image;
    std::printf(
        "[spot_detector_bench] %zu images, %u thread(s): %.3f s per image, "
        "%.3f CPU s (%d stable spots)\n",
        images.size(), threads, per_image, cpu_per_image, stable);
    runs.push_back({{"threads", threads},
                    {"monte_carlo_iterations", options.monte_carlo_iterations},
                    {"wall_s_per_image", per_image},
                    {"cpu_s_per_image", cpu_per_image},
                    {"speed_up", one_thread / per_image},
                    {"stable_spots", stable}});
  }
  double load = -1.0;
  getloadavg(&load, 1);
  const nlohmann::json record = {
      {"benchmark",
       "laser-spot detector (DetectSpots), 1024x768, 4 lasers, aux shifted"},
      {"camera", "SIMPLE_RADIAL 1024x768"},
      {"images", images.size()},
      {"target_s_per_image", 0.2},
      {"cores", cores},
      // Other work on the machine slows the runs; this says how much there
      // was (1-minute load average when the runs ended).
      {"load_average", load},
      {"runs", runs}};
  WriteFilesAtomically(
      {{argv[1],
        [&](std::ostream& stream) { stream << record.dump(2) << "\n"; }}},
      false);
  return 0;
}
