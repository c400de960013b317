// Speed of our covariance (Schur complement, one Cholesky, sparse inverse)
// against ceres::Covariance with SPARSE_QR on the same problems, and of our
// bundle adjuster (no priors) against colmap bundle_adjuster, from 100 to
// 5000 images (issue 16, acceptance 4: >= 10x faster than Ceres for the
// camera marginals at >= 500 images; 2000 images in < 10 s on 2 cores).
//
// The problems are large uwsim lawnmower surveys of the seafloor, observed
// without rendering (sim/observe.h: the tracks a perfect matcher would
// give, 0.5 px noise) and written as COLMAP models: the covariance runs on
// the model at the true poses, the adjusters on the same model with
// perturbed cameras and focal length (bench/perturbed_model.h). Every run
// is a separate process timed from outside (wall, CPU, peak memory), both
// programs with every core. ceres::Covariance grows much faster than ours:
// a size is skipped for it when its last time, extrapolated
// quadratically, exceeds --ceres_limit_s; the bench records that.
//
// Both engines' per-image 6x6 marginals are read back from covariance.bin
// and compared: a speed-up of a different answer would mean nothing.
// Fails (exit 1) when ours is not >= 10x faster at a size >= 500 images
// that Ceres ran, when Ceres ran at no such size, or when the engines
// disagree by more than 1e-6.
//
//   covariance_speed_bench OUT.json --uwcolmap PATH
//       [--sizes 100,200,500,1000,2000,5000] [--points_per_image 150]
//       [--ceres_limit_s 1800] [--ba_max_images 5000] [--seed 1]
//       [--keep_work 1]   (models and outputs stay in
//       $TMPDIR/uw_covariance_bench)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/bundle_adjuster_runs.h"
#include "bench/perturbed_model.h"
#include "bench/timed_run.h"
#include "bench/wall_clock.h"
#include "colmap_plugins/ba/covariance_files.h"
#include "colmap_plugins/scene/model_io.h"
#include "common/util/file.h"
#include "sim/observe.h"
#include "sim/sim_config.h"
#include "sim/survey.h"
#include "sim/world.h"

namespace {

namespace fs = std::filesystem;

struct BenchOptions {
  std::string uwcolmap;
  std::vector<int> sizes = {100, 200, 500, 1000, 2000, 5000};
  int points_per_image = 150;
  double ceres_limit_s = 1800.0;
  int ba_max_images = 5000;
  uint64_t seed = 1;
  bool keep_work = false;  // keep the models and outputs in the work folder
};

// A lawnmower of exactly `num_images` stations over a seafloor grown until
// the plan holds them; the floor's mesh coarsened to 10 cm (the relief at
// 2.5 m altitude needs no finer, and observing stays linear in its size).
struct Survey {
  uw::sim::World world;
  uw::Reconstruction truth;
};

Survey PlanLargeSurvey(int num_images, uint64_t seed) {
  const uw::Camera camera = uw::sim::SimConfig::DefaultCamera();
  uw::sim::SurveyOptions survey;
  survey.coverage_along = 0.9;
  survey.coverage_across = 0.9;
  survey.max_images = num_images;
  // ~0.86 m^2 of new floor per image at the default stand-off and overlaps.
  double area_m2 = 1.2 * num_images * 0.86 / (0.9 * 0.9);
  for (int attempt = 0; attempt < 6; ++attempt, area_m2 *= 1.3) {
    uw::sim::WorldOptions options;
    options.seafloor.vertex_spacing_m = 0.1;
    options.seafloor.length_m = std::sqrt(1.5 * area_m2) + 4.0;
    options.seafloor.width_m = std::sqrt(area_m2 / 1.5) + 4.0;
    Survey result;
    result.world =
        uw::sim::MakeWorld(uw::sim::WorldKind::kSeafloor, options, seed);
    const std::vector<uw::sim::SurveyStation> stations = uw::sim::PlanSurvey(
        uw::sim::SurveyKind::kLawnmower, result.world, camera, survey, seed);
    if (static_cast<int>(stations.size()) < num_images) continue;
    result.truth.AddCamera(camera);
    uw::image_t image_id = 0;
    for (const uw::sim::SurveyStation& station : stations) {
      uw::Image image;
      image.image_id = ++image_id;
      image.camera_id = camera.camera_id;
      image.name = station.image_name + ".png";
      image.cam_from_world = station.cam_from_world;
      result.truth.AddImage(image);
    }
    return result;
  }
  throw std::runtime_error("no seafloor held a plan of " +
                           std::to_string(num_images) + " images");
}

nlohmann::json TimesJson(const uw::bench::ProcessTimes& times) {
  return {{"wall_s", times.wall_s},
          {"cpu_s", times.cpu_s},
          {"max_rss_mb", times.max_rss_mb}};
}

// uwcolmap covariance_estimator, held gauge (COLMAP's), on `model`.
uw::bench::ProcessTimes RunCovariance(const BenchOptions& options,
                                      const fs::path& model,
                                      const fs::path& dir,
                                      const std::string& method, bool points,
                                      int threads) {
  fs::remove_all(dir);
  fs::create_directories(dir.parent_path());
  return uw::bench::RunTimed(
      {options.uwcolmap, "covariance_estimator", "--input_path", model.string(),
       "--output_path", dir.string(), "--Covariance.gauge", "held",
       "--Covariance.method", method, "--Covariance.points", points ? "1" : "0",
       "--num_threads", std::to_string(threads)},
      dir.string() + ".log");
}

// Worst relative Frobenius difference of the free images' 6x6 marginals.
double WorstPoseDifference(const fs::path& ours, const fs::path& theirs,
                           const uw::Reconstruction& model) {
  const uw::BundleCovariance a =
      uw::ReadCovarianceSidecar(ours / "covariance.bin", model);
  const uw::BundleCovariance b =
      uw::ReadCovarianceSidecar(theirs / "covariance.bin", model);
  if (a.images.size() != b.images.size()) {
    throw std::runtime_error("the two covariances hold different images");
  }
  double worst = 0.0;
  for (size_t i = 0; i < a.images.size(); ++i) {
    if (a.images[i].held) continue;
    worst = std::max(
        worst,
        (a.images[i].rotation_center - b.images[i].rotation_center).norm() /
            a.images[i].rotation_center.norm());
  }
  return worst;
}

// Slope of log(time) against log(images) between consecutive sizes.
nlohmann::json GrowthExponents(const nlohmann::json& sizes, const char* run) {
  nlohmann::json exponents = nlohmann::json::array();
  for (size_t k = 1; k < sizes.size(); ++k) {
    const nlohmann::json& a = sizes[k - 1];
    const nlohmann::json& b = sizes[k];
    if (!a.contains(run) || !b.contains(run)) continue;
    exponents.push_back(
        {{"from_images", a["images"]},
         {"to_images", b["images"]},
         {"exponent", std::log(b[run]["wall_s"].get<double>() /
                               a[run]["wall_s"].get<double>()) /
                          std::log(b["images"].get<double>() /
                                   a["images"].get<double>())}});
  }
  return exponents;
}

std::vector<int> ParseSizes(const std::string& text) {
  std::vector<int> sizes;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) sizes.push_back(std::stoi(item));
  if (sizes.empty()) throw std::runtime_error("--sizes is empty");
  return sizes;
}

}  // namespace

int Main(int argc, char** argv) {
  if (argc < 2 || std::string(argv[1]).rfind("--", 0) == 0) {
    std::fprintf(stderr,
                 "usage: covariance_speed_bench OUT.json --uwcolmap PATH "
                 "[--sizes 100,200,500,1000,2000,5000] [--points_per_image "
                 "150] [--ceres_limit_s 1800] [--ba_max_images 5000] "
                 "[--seed 1] [--keep_work 1]\n");
    return 2;
  }
  BenchOptions options;
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    const std::string value = argv[i + 1];
    if (flag == "--uwcolmap") {
      options.uwcolmap = value;
    } else if (flag == "--sizes") {
      options.sizes = ParseSizes(value);
    } else if (flag == "--points_per_image") {
      options.points_per_image = std::stoi(value);
    } else if (flag == "--ceres_limit_s") {
      options.ceres_limit_s = std::stod(value);
    } else if (flag == "--ba_max_images") {
      options.ba_max_images = std::stoi(value);
    } else if (flag == "--seed") {
      options.seed = std::stoull(value);
    } else if (flag == "--keep_work") {
      options.keep_work = value == "1";
    } else {
      std::fprintf(stderr, "covariance_speed_bench: unknown flag %s\n",
                   flag.c_str());
      return 2;
    }
  }
  if (options.uwcolmap.empty()) {
    throw std::runtime_error("--uwcolmap is required");
  }
  const int threads =
      static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const fs::path work = fs::temp_directory_path() / "uw_covariance_bench";
  fs::remove_all(work);

  nlohmann::json records = nlohmann::json::array();
  std::vector<std::string> failures;
  double last_ceres_s = 0.0;
  int last_ceres_images = 0;
  for (const int num_images : options.sizes) {
    const fs::path dir = work / std::to_string(num_images);
    fs::create_directories(dir);
    double start = uw::bench::WallSeconds();
    const Survey survey = PlanLargeSurvey(num_images, options.seed);
    uw::sim::ObserveOptions observe;
    observe.num_points = options.points_per_image * num_images;
    observe.seed = options.seed;
    uw::sim::ObserveSummary summary;
    const uw::Reconstruction model = uw::sim::ObserveModel(
        survey.truth, survey.world.mesh, observe, &summary);
    uw::WriteModel(model, dir / "model", uw::ModelFormat::kBinary);
    uw::Reconstruction perturbed = model;
    uw::bench::PerturbModel(uw::bench::PerturbationOptions(), &perturbed);
    uw::WriteModel(perturbed, dir / "perturbed", uw::ModelFormat::kBinary);
    const double generate_s = uw::bench::WallSeconds() - start;
    std::printf(
        "[covariance_speed_bench] %d images: %zu points, %zu observations "
        "(%.0f per image), floor %.0f x %.0f m, observed in %.1f s\n",
        num_images, summary.num_points, summary.num_observations,
        static_cast<double>(summary.num_observations) / num_images,
        survey.world.bounds.sizes().x(), survey.world.bounds.sizes().y(),
        generate_s);
    std::fflush(stdout);

    nlohmann::json record = {{"images", num_images},
                             {"points3D", summary.num_points},
                             {"observations", summary.num_observations},
                             {"generate_s", generate_s}};
    const uw::bench::ProcessTimes ours_cameras = RunCovariance(
        options, dir / "model", dir / "ours_cameras", "schur", false, threads);
    record["ours_cameras"] = TimesJson(ours_cameras);
    const uw::bench::ProcessTimes ours_points = RunCovariance(
        options, dir / "model", dir / "ours_points", "schur", true, threads);
    record["ours_cameras_and_points"] = TimesJson(ours_points);
    std::printf(
        "[covariance_speed_bench] %d images: ours %.2f s (cameras), %.2f s "
        "(and every point), peak %.0f MB\n",
        num_images, ours_cameras.wall_s, ours_points.wall_s,
        ours_points.max_rss_mb);
    std::fflush(stdout);

    const double predicted_ceres_s =
        last_ceres_images == 0
            ? 0.0
            : last_ceres_s *
                  std::pow(static_cast<double>(num_images) / last_ceres_images,
                           2.0);
    if (predicted_ceres_s > options.ceres_limit_s) {
      record["ceres_skipped"] = "extrapolated " +
                                std::to_string(predicted_ceres_s) +
                                " s exceeds --ceres_limit_s";
      std::printf(
          "[covariance_speed_bench] %d images: ceres::Covariance skipped "
          "(extrapolated %.0f s)\n",
          num_images, predicted_ceres_s);
    } else {
      const uw::bench::ProcessTimes ceres =
          RunCovariance(options, dir / "model", dir / "ceres_cameras",
                        "ceres_sparse_qr", false, threads);
      record["ceres_cameras"] = TimesJson(ceres);
      last_ceres_s = ceres.wall_s;
      last_ceres_images = num_images;
      const double worst = WorstPoseDifference(dir / "ours_cameras",
                                               dir / "ceres_cameras", model);
      const double ratio = ceres.wall_s / ours_cameras.wall_s;
      record["ratio_ceres_over_ours_wall"] = ratio;
      record["ratio_ceres_over_ours_cpu"] = ceres.cpu_s / ours_cameras.cpu_s;
      record["ratio_ceres_over_ours_memory"] =
          ceres.max_rss_mb / ours_cameras.max_rss_mb;
      record["worst_pose_marginal_difference"] = worst;
      std::printf(
          "[covariance_speed_bench] %d images: ceres::Covariance SPARSE_QR "
          "%.2f s, peak %.0f MB: %.1fx ours; marginals differ by %.2g\n",
          num_images, ceres.wall_s, ceres.max_rss_mb, ratio, worst);
      if (num_images >= 500 && ratio < 10.0) {
        failures.push_back("at " + std::to_string(num_images) +
                           " images ours is only " + std::to_string(ratio) +
                           "x faster than ceres::Covariance");
      }
      if (!(worst < 1e-6)) {
        failures.push_back("at " + std::to_string(num_images) +
                           " images the marginals differ by " +
                           std::to_string(worst));
      }
    }
    std::fflush(stdout);

    if (num_images <= options.ba_max_images) {
      const uw::bench::Run colmap =
          uw::bench::ColmapRun(dir / "perturbed", dir / "colmap_ba");
      const uw::bench::Run ours = uw::bench::OursRun(
          options.uwcolmap, dir / "perturbed", dir / "ours_ba", threads);
      const auto ba_json = [](const uw::bench::Run& run) {
        nlohmann::json json = TimesJson(run.process);
        json["solve_s"] = run.solve_s;
        json["iterations"] = run.iterations;
        json["initial_rms_px"] = run.initial_rms_px;
        json["final_rms_px"] = run.final_rms_px;
        return json;
      };
      record["colmap_bundle_adjuster"] = ba_json(colmap);
      record["ours_bundle_adjuster"] = ba_json(ours);
      record["ratio_ba_ours_over_colmap_wall"] =
          ours.process.wall_s / colmap.process.wall_s;
      record["ratio_ba_ours_over_colmap_final_rms"] =
          ours.final_rms_px / colmap.final_rms_px;
      // colmap 3.8 sets Ceres' tolerances to 0: it always runs its 100
      // iterations, ours stops at convergence; per iteration compares the
      // work of one step.
      record["ratio_ba_ours_over_colmap_solve_per_iteration"] =
          (ours.solve_s / std::max(1, ours.iterations)) /
          (colmap.solve_s / std::max(1, colmap.iterations));
      std::printf(
          "[covariance_speed_bench] %d images: bundle_adjuster colmap %.1f s "
          "(%d iterations, peak %.0f MB, RMS %.6f px), ours %.1f s (%d "
          "iterations, peak %.0f MB, RMS %.6f px), from %.6f px\n",
          num_images, colmap.process.wall_s, colmap.iterations,
          colmap.process.max_rss_mb, colmap.final_rms_px, ours.process.wall_s,
          ours.iterations, ours.process.max_rss_mb, ours.final_rms_px,
          ours.initial_rms_px);
      std::fflush(stdout);
    }
    records.push_back(record);
    if (!options.keep_work) fs::remove_all(dir);
  }
  bool ceres_at_500 = false;
  for (const nlohmann::json& record : records) {
    ceres_at_500 |=
        record["images"].get<int>() >= 500 && record.contains("ceres_cameras");
  }
  if (!ceres_at_500) {
    failures.push_back("ceres::Covariance ran at no size >= 500 images");
  }

  const nlohmann::json result = {
      {"benchmark",
       "covariance of the camera poses: uwcolmap covariance_estimator "
       "(schur) vs the same problem through ceres::Covariance SPARSE_QR "
       "(--Covariance.method ceres_sparse_qr), held gauge; and "
       "bundle_adjuster (no priors) vs colmap 3.8 bundle_adjuster on the "
       "perturbed model; uwsim seafloor lawnmowers observed with 0.5 px "
       "noise"},
      {"threads", threads},
      {"points_per_image", options.points_per_image},
      {"ceres_limit_s", options.ceres_limit_s},
      {"ba_max_images", options.ba_max_images},
      {"seed", options.seed},
      {"load_average_1min_at_end", uw::bench::LoadAverage1Min()},
      {"acceptance",
       "ratio_ceres_over_ours_wall >= 10 at >= 500 images; aim: "
       "ours_cameras.wall_s < 10 at 2000 images"},
      {"failures", failures},
      {"sizes", records},
      {"growth_exponents",
       {{"ours_cameras", GrowthExponents(records, "ours_cameras")},
        {"ours_cameras_and_points",
         GrowthExponents(records, "ours_cameras_and_points")},
        {"ceres_cameras", GrowthExponents(records, "ceres_cameras")},
        {"ours_bundle_adjuster",
         GrowthExponents(records, "ours_bundle_adjuster")},
        {"colmap_bundle_adjuster",
         GrowthExponents(records, "colmap_bundle_adjuster")}}}};
  uw::WriteFilesAtomically(
      {{argv[1],
        [&](std::ostream& stream) { stream << result.dump(2) << "\n"; }}},
      false);
  if (!options.keep_work) fs::remove_all(work);
  for (const std::string& failure : failures) {
    std::fprintf(stderr, "covariance_speed_bench: %s\n", failure.c_str());
  }
  return failures.empty() ? 0 : 1;
}

int main(int argc, char** argv) {
  try {
    return Main(argc, argv);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "covariance_speed_bench: %s\n", error.what());
    return 1;
  }
}
