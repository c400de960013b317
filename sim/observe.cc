#include "sim/observe.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <unordered_map>
#include <unordered_set>

#include <tbb/parallel_for.h>

#include "colmap_plugins/align/visibility.h"
#include "colmap_plugins/scene/model_io.h"
#include "common/mesh/ray_caster.h"
#include "common/util/error.h"
#include "common/util/random.h"

namespace uw::sim {
namespace {

namespace fs = std::filesystem;

constexpr double kDegToRad = M_PI / 180.0;

// Independent random streams for the three uses of the seed, so that the
// noise of a point does not depend on how many candidates were rejected
// before it, nor the perturbation on the points.
enum class Stream : uint64_t { kSampling = 1, kNoise = 2, kPerturbation = 3 };
SplitMix64Stream MakeStream(uint64_t seed, Stream stream) {
  return SplitMix64Stream(SplitMix64(seed ^ SplitMix64(uint64_t(stream))));
}

Eigen::Vector3d Gaussian3(SplitMix64Stream* random) {
  const double x = random->Gaussian();
  const double y = random->Gaussian();
  return {x, y, random->Gaussian()};
}

// Cumulative areas of the triangles whose centroid some image has in view
// (0 for the others): uniform sampling over the surface the survey saw.
std::vector<double> CumulativeSeenArea(const TriangleMesh& mesh,
                                       const SurfaceVisibility& visibility) {
  std::vector<double> areas(mesh.triangles.size(), 0.0);
  tbb::parallel_for(size_t(0), mesh.triangles.size(), [&](size_t t) {
    const Eigen::Vector3i& triangle = mesh.triangles[t];
    const Eigen::Vector3d& a = mesh.vertices[triangle[0]];
    const Eigen::Vector3d& b = mesh.vertices[triangle[1]];
    const Eigen::Vector3d& c = mesh.vertices[triangle[2]];
    const Eigen::Vector3d centroid = (a + b + c) / 3.0;
    for (size_t view = 0; view < visibility.NumViews(); ++view) {
      if (visibility.PixelInView(view, centroid).has_value()) {
        areas[t] = 0.5 * (b - a).cross(c - a).norm();
        return;
      }
    }
  });
  for (size_t t = 1; t < areas.size(); ++t) areas[t] += areas[t - 1];
  return areas;
}

Eigen::Vector3d SamplePoint(const TriangleMesh& mesh,
                            const std::vector<double>& cumulative_area,
                            SplitMix64Stream* random) {
  const double target = random->Uniform() * cumulative_area.back();
  const size_t t = std::min<size_t>(
      std::upper_bound(cumulative_area.begin(), cumulative_area.end(), target) -
          cumulative_area.begin(),
      cumulative_area.size() - 1);
  const Eigen::Vector3i& triangle = mesh.triangles[t];
  // Uniform over the triangle (Osada et al. 2002).
  const double r1 = std::sqrt(random->Uniform());
  const double r2 = random->Uniform();
  return (1.0 - r1) * mesh.vertices[triangle[0]] +
         r1 * (1.0 - r2) * mesh.vertices[triangle[1]] +
         r1 * r2 * mesh.vertices[triangle[2]];
}

// A uniformly random rotation: a normalised 4D Gaussian.
Eigen::Quaterniond RandomRotation(SplitMix64Stream* random) {
  const double w = random->Gaussian();
  const Eigen::Vector3d xyz = Gaussian3(random);
  return Eigen::Quaterniond(w, xyz.x(), xyz.y(), xyz.z()).normalized();
}

// Moves the true model by a random similarity (scale 0.3-3, any rotation,
// a translation of the order of the scene's size) after turning and moving
// each camera a little, so that bundle adjustment has to recover both the
// gauge and the poses.
Sim3d Perturb(const ObserveOptions& options, Reconstruction* model) {
  SplitMix64Stream random = MakeStream(options.seed, Stream::kPerturbation);
  Eigen::AlignedBox3d extent;
  for (const Image& image : model->Images()) {
    extent.extend(image.ProjectionCenter());
  }
  for (const Point3D& point : model->Points3D()) extent.extend(point.xyz);
  Sim3d model_from_world;
  model_from_world.scale =
      std::exp(random.Uniform(std::log(0.3), std::log(3.0)));
  model_from_world.rotation = RandomRotation(&random);
  model_from_world.translation =
      (extent.diagonal().norm() + 1.0) * Gaussian3(&random);
  for (Image& image : model->Images()) {
    const Eigen::Vector3d rotation_vector =
        options.perturb_rotation_deg * kDegToRad * Gaussian3(&random);
    const Eigen::Vector3d centre =
        image.ProjectionCenter() +
        options.perturb_position_m * Gaussian3(&random);
    const Eigen::Quaterniond turn(Eigen::AngleAxisd(
        rotation_vector.norm(), rotation_vector.norm() > 0.0
                                    ? rotation_vector.normalized()
                                    : Eigen::Vector3d::UnitX()));
    image.cam_from_world.rotation =
        (turn * image.cam_from_world.rotation.normalized()).normalized();
    image.cam_from_world.translation =
        -(image.cam_from_world.rotation * centre);
  }
  TransformReconstruction(model_from_world, model);
  return model_from_world;
}

// Mean reprojection error of each track in the model as it stands.
void SetReprojectionErrors(Reconstruction* model) {
  for (Point3D& point : model->Points3D()) {
    double sum = 0.0;
    for (const TrackElement& element : point.track) {
      const Image& image = *model->FindImage(element.image_id);
      const Camera& camera = *model->FindCamera(image.camera_id);
      sum += (camera.ImgFromCam(image.cam_from_world * point.xyz) -
              image.points2D[element.point2D_idx].xy)
                 .norm();
    }
    point.error = sum / static_cast<double>(point.track.size());
  }
}

// The images a mapper would register (ObserveOptions::
// min_registration_points), with the points two or more of them still see;
// ids, names and pixels as in `model`. Adds the dropped images to
// `summary` and recounts its points and observations.
Reconstruction KeepRegistrableImages(const Reconstruction& model,
                                     int min_points, ObserveSummary* summary) {
  std::unordered_set<image_t> dropped;
  const auto kept_track_length = [&](const Point3D& point) {
    return std::count_if(point.track.begin(), point.track.end(),
                         [&](const TrackElement& element) {
                           return dropped.count(element.image_id) == 0;
                         });
  };
  // Dropping an image shortens tracks through it, which can leave another
  // image short: repeat until none is.
  for (bool changed = true; changed;) {
    std::unordered_map<image_t, int> support;
    for (const Point3D& point : model.Points3D()) {
      if (kept_track_length(point) < 3) continue;
      for (const TrackElement& element : point.track)
        ++support[element.image_id];
    }
    changed = false;
    for (const Image& image : model.Images()) {
      if (dropped.count(image.image_id) == 0 &&
          support[image.image_id] < min_points) {
        dropped.insert(image.image_id);
        summary->dropped_images.push_back(image.name);
        changed = true;
      }
    }
  }
  if (dropped.empty()) return model;

  Reconstruction kept;
  kept.layout = model.layout;
  for (const Camera& camera : model.Cameras()) kept.AddCamera(camera);
  std::unordered_map<image_t, size_t> kept_index;
  for (const Image& image : model.Images()) {
    if (dropped.count(image.image_id) != 0) continue;
    kept_index[image.image_id] = kept.Images().size();
    Image copy = image;
    copy.points2D.clear();
    kept.AddImage(std::move(copy));
  }
  summary->num_points = 0;
  summary->num_observations = 0;
  for (const Point3D& point : model.Points3D()) {
    if (kept_track_length(point) < 2) continue;
    Point3D copy = point;
    copy.track.clear();
    for (const TrackElement& element : point.track) {
      if (dropped.count(element.image_id) != 0) continue;
      Image& image = kept.Images()[kept_index.at(element.image_id)];
      copy.track.push_back(
          {image.image_id, static_cast<point2D_t>(image.points2D.size())});
      image.points2D.push_back(
          model.FindImage(element.image_id)->points2D[element.point2D_idx]);
    }
    ++summary->num_points;
    summary->num_observations += copy.track.size();
    kept.AddPoint3D(std::move(copy));
  }
  return kept;
}

}  // namespace

std::string ObserveInitName(ObserveInit init) {
  switch (init) {
    case ObserveInit::kTruth:
      return "truth";
    case ObserveInit::kPerturbed:
      return "perturbed";
  }
  throw ErrorAt("unknown observe init ", static_cast<int>(init));
}

ObserveInit ObserveInitFromName(const std::string& name) {
  for (const ObserveInit init :
       {ObserveInit::kTruth, ObserveInit::kPerturbed}) {
    if (ObserveInitName(init) == name) return init;
  }
  throw ErrorAt("unknown observe init '", name, "' (truth | perturbed)");
}

void ObserveOptions::Check() const {
  if (!(std::isfinite(pixel_sigma) && pixel_sigma >= 0.0)) {
    throw ErrorAt("observe option pixel_sigma = ", pixel_sigma,
                  " must be finite and >= 0");
  }
  if (num_points < 1) {
    throw ErrorAt("observe option num_points = ", num_points, " must be >= 1");
  }
  if (!(std::isfinite(perturb_rotation_deg) && perturb_rotation_deg >= 0.0 &&
        perturb_rotation_deg <= 10.0)) {
    throw ErrorAt("observe option perturb_rotation_deg = ",
                  perturb_rotation_deg, " must be in [0, 10]");
  }
  if (!(std::isfinite(perturb_position_m) && perturb_position_m >= 0.0)) {
    throw ErrorAt("observe option perturb_position_m = ", perturb_position_m,
                  " must be finite and >= 0");
  }
  if (min_registration_points < 0) {
    throw ErrorAt("observe option min_registration_points = ",
                  min_registration_points, " must be >= 0");
  }
}

Reconstruction ObserveModel(const Reconstruction& truth,
                            const TriangleMesh& mesh,
                            const ObserveOptions& options,
                            ObserveSummary* summary) {
  options.Check();
  if (truth.Images().size() < 2) {
    throw ErrorAt("observe needs at least 2 images, the model has ",
                  truth.Images().size());
  }
  const RayCaster caster(mesh);
  const SurfaceVisibility visibility(truth, caster);
  const std::vector<double> cumulative_area =
      CumulativeSeenArea(mesh, visibility);
  if (!(cumulative_area.back() > 0.0)) {
    throw ErrorAt("no triangle of the mesh is in view of any image");
  }

  Reconstruction model;
  model.layout = truth.layout;
  for (const Camera& camera : truth.Cameras()) model.AddCamera(camera);
  for (const Image& true_image : truth.Images()) {
    Image image = true_image;
    image.points2D.clear();
    model.AddImage(image);
  }

  ObserveSummary result;
  SplitMix64Stream sampling = MakeStream(options.seed, Stream::kSampling);
  SplitMix64Stream noise = MakeStream(options.seed, Stream::kNoise);
  const size_t wanted = static_cast<size_t>(options.num_points);
  const size_t max_candidates = ObserveOptions::kMaxCandidatesPerPoint * wanted;
  // Candidates are drawn in order and observed in parallel; accepting them
  // in order keeps the result independent of the thread count.
  while (result.num_points < wanted && result.num_candidates < max_candidates) {
    const size_t batch = std::min(std::max<size_t>(wanted, 1024),
                                  max_candidates - result.num_candidates);
    std::vector<Eigen::Vector3d> candidates(batch);
    for (Eigen::Vector3d& candidate : candidates) {
      candidate = SamplePoint(mesh, cumulative_area, &sampling);
    }
    std::vector<std::vector<SurfaceObservation>> observations(batch);
    tbb::parallel_for(size_t(0), batch, [&](size_t i) {
      observations[i] = visibility.Observe(candidates[i]);
    });
    for (size_t i = 0; i < batch && result.num_points < wanted; ++i) {
      ++result.num_candidates;
      if (observations[i].size() < 2) continue;
      Point3D point;
      point.point3D_id = ++result.num_points;
      point.xyz = candidates[i];
      point.color.setConstant(128);
      for (const SurfaceObservation& observation : observations[i]) {
        Image& image = model.Images()[observation.view];
        Point2D point2D;
        const double dx = noise.Gaussian();
        point2D.xy =
            observation.pixel +
            options.pixel_sigma * Eigen::Vector2d(dx, noise.Gaussian());
        point2D.point3D_id = point.point3D_id;
        point.track.push_back(
            {image.image_id, static_cast<point2D_t>(image.points2D.size())});
        image.points2D.push_back(point2D);
        ++result.num_observations;
      }
      model.AddPoint3D(std::move(point));
    }
  }
  if (options.min_registration_points > 0) {
    model =
        KeepRegistrableImages(model, options.min_registration_points, &result);
  }
  if (options.init == ObserveInit::kPerturbed) {
    result.model_from_world = Perturb(options, &model);
  }
  SetReprojectionErrors(&model);
  if (summary != nullptr) *summary = result;
  return model;
}

ObserveSummary ObserveSimulation(const fs::path& sim_dir,
                                 const fs::path& output_dir,
                                 const ObserveOptions& options) {
  options.Check();
  if (fs::exists(output_dir) && !fs::is_empty(output_dir)) {
    throw ErrorAt(output_dir.string(),
                  ": output folder exists and is not empty; choose a new one");
  }
  const fs::path truth_dir = sim_dir / "truth";
  for (const char* name : {"cameras.txt", "images.txt", "mesh.ply"}) {
    if (!fs::is_regular_file(truth_dir / name)) {
      throw ErrorAt((truth_dir / name).string(), ": missing; is ",
                    sim_dir.string(), " an output folder of uwsim generate?");
    }
  }
  const Reconstruction truth = ReadModelText(truth_dir, ModelLayout::kColmap3);
  ObserveSummary summary;
  const Reconstruction model =
      ObserveModel(truth, ReadPly(truth_dir / "mesh.ply"), options, &summary);
  WriteModel(model, output_dir, ModelFormat::kText);
  return summary;
}

}  // namespace uw::sim
