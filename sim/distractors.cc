#include "sim/distractors.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "common/util/error.h"
#include "common/util/json_fields.h"
#include "common/util/random.h"

namespace uw::sim {
namespace {

uint64_t CellKey(const Eigen::Vector3d& point, double cell_m) {
  // 21 bits per axis: +-1e6 cells, kilometres at centimetre cells.
  uint64_t key = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const int64_t index =
        static_cast<int64_t>(std::floor(point(axis) / cell_m));
    key = (key << 21) | (static_cast<uint64_t>(index + (1 << 20)) & 0x1FFFFF);
  }
  return key;
}

}  // namespace

Distractor Shell(const Eigen::Vector3d& centre, double radius_m) {
  return {centre, radius_m, Eigen::Vector3f(0.9f, 0.9f, 0.9f), {}};
}

Distractor Debris(const Eigen::Vector3d& centre, double radius_m,
                  const Eigen::Vector3f& albedo) {
  return {centre, radius_m, albedo, {}};
}

Distractor ShinyObject(const Eigen::Vector3d& centre, double radius_m) {
  // (n.h)^50 falls to 1/e at 11.5 deg; weight 0.9 peaks like white paper.
  return {centre, radius_m, Eigen::Vector3f(0.3f, 0.3f, 0.3f), {0.9f, 50.0f}};
}

const std::vector<Eigen::Vector3f>& DebrisColours() {
  static const std::vector<Eigen::Vector3f> colours = {{0.85f, 0.75f, 0.1f},
                                                       {0.15f, 0.6f, 0.2f},
                                                       {0.1f, 0.3f, 0.8f},
                                                       {0.6f, 0.35f, 0.15f},
                                                       {0.85f, 0.85f, 0.8f}};
  return colours;
}

void DistractorOptions::Check() const {
  const auto fail = [](const char* field, double value, const char* rule) {
    throw ErrorAt("distractors: ", field, " = ", value, ": ", rule);
  };
  for (const auto& [field, value] : {std::pair("shells_per_m2", shells_per_m2),
                                     std::pair("debris_per_m2", debris_per_m2),
                                     std::pair("shiny_per_m2", shiny_per_m2)}) {
    if (!(value >= 0.0 && value <= 100.0))
      fail(field, value, "must be in [0, 100]");
  }
  if (!(min_radius_m > 0.0)) fail("min_radius_m", min_radius_m, "must be > 0");
  if (!(max_radius_m >= min_radius_m && max_radius_m <= 1.0)) {
    fail("max_radius_m", max_radius_m, "must be in [min_radius_m, 1]");
  }
}

void to_json(nlohmann::json& json, const DistractorOptions& options) {
  json = {{"shells_per_m2", options.shells_per_m2},
          {"debris_per_m2", options.debris_per_m2},
          {"shiny_per_m2", options.shiny_per_m2},
          {"min_radius_m", options.min_radius_m},
          {"max_radius_m", options.max_radius_m}};
}

void from_json(const nlohmann::json& json, DistractorOptions& options) {
  JsonFields fields(json, "distractors");
  fields.Read("shells_per_m2", &options.shells_per_m2);
  fields.Read("debris_per_m2", &options.debris_per_m2);
  fields.Read("shiny_per_m2", &options.shiny_per_m2);
  fields.Read("min_radius_m", &options.min_radius_m);
  fields.Read("max_radius_m", &options.max_radius_m);
  fields.RejectUnknown();
}

std::vector<Distractor> ScatterDistractors(const TriangleMesh& mesh,
                                           const DistractorOptions& options,
                                           uint64_t seed) {
  options.Check();
  std::vector<double> cumulative_area;
  double area = 0.0;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    const Eigen::Vector3d& a = mesh.vertices[t(0)];
    area +=
        0.5 * (mesh.vertices[t(1)] - a).cross(mesh.vertices[t(2)] - a).norm();
    cumulative_area.push_back(area);
  }
  std::vector<Distractor> distractors;
  if (!(area > 0.0)) return distractors;
  SplitMix64Stream random(SplitMix64(seed ^ 0xD157AC7085ull));
  const auto point_on_mesh = [&] {
    const double at = random.Uniform(0.0, area);
    const size_t triangle = std::min<size_t>(
        std::upper_bound(cumulative_area.begin(), cumulative_area.end(), at) -
            cumulative_area.begin(),
        mesh.triangles.size() - 1);
    const Eigen::Vector3i& t = mesh.triangles[triangle];
    double u = random.Uniform();
    double v = random.Uniform();
    if (u + v > 1.0) {
      u = 1.0 - u;
      v = 1.0 - v;
    }
    const Eigen::Vector3d& a = mesh.vertices[t(0)];
    return Eigen::Vector3d(a + u * (mesh.vertices[t(1)] - a) +
                           v * (mesh.vertices[t(2)] - a));
  };
  const auto radius = [&] {
    return random.Uniform(options.min_radius_m, options.max_radius_m);
  };
  const auto count = [&](double per_m2) {
    return static_cast<size_t>(std::llround(per_m2 * area));
  };
  for (size_t i = 0; i < count(options.shells_per_m2); ++i) {
    const Eigen::Vector3d centre = point_on_mesh();
    distractors.push_back(Shell(centre, radius()));
  }
  for (size_t i = 0; i < count(options.debris_per_m2); ++i) {
    const Eigen::Vector3d centre = point_on_mesh();
    const double r = radius();
    const std::vector<Eigen::Vector3f>& colours = DebrisColours();
    distractors.push_back(
        Debris(centre, r, colours[random.Next() % colours.size()]));
  }
  for (size_t i = 0; i < count(options.shiny_per_m2); ++i) {
    const Eigen::Vector3d centre = point_on_mesh();
    distractors.push_back(ShinyObject(centre, radius()));
  }
  return distractors;
}

DistractorTexture::DistractorTexture(std::shared_ptr<const Texture> base,
                                     std::vector<Distractor> distractors)
    : base_(std::move(base)), distractors_(std::move(distractors)) {
  if (base_ == nullptr) throw ErrorAt("DistractorTexture: no base texture");
  double max_radius = 0.0;
  for (const Distractor& d : distractors_) {
    if (!(d.radius_m > 0.0) || !d.centre_in_world.allFinite()) {
      throw ErrorAt("DistractorTexture: a distractor at ",
                    d.centre_in_world.transpose(), " of radius ", d.radius_m);
    }
    max_radius = std::max(max_radius, d.radius_m);
    shiny_ = shiny_ || d.shine.weight > 0.0f;
  }
  cell_m_ = std::max(2.0 * max_radius, 1e-3);
  for (size_t i = 0; i < distractors_.size(); ++i) {
    const Distractor& d = distractors_[i];
    const Eigen::Vector3d low =
        ((d.centre_in_world.array() - d.radius_m) / cell_m_).floor();
    const Eigen::Vector3d high =
        ((d.centre_in_world.array() + d.radius_m) / cell_m_).floor();
    for (double x = low.x(); x <= high.x(); ++x) {
      for (double y = low.y(); y <= high.y(); ++y) {
        for (double z = low.z(); z <= high.z(); ++z) {
          cells_[CellKey((Eigen::Vector3d(x, y, z).array() + 0.5) * cell_m_,
                         cell_m_)]
              .push_back(static_cast<int>(i));
        }
      }
    }
  }
}

const Distractor* DistractorTexture::At(
    const Eigen::Vector3d& point_in_world) const {
  const auto cell = cells_.find(CellKey(point_in_world, cell_m_));
  if (cell == cells_.end()) return nullptr;
  // The last listed wins where two overlap.
  const Distractor* found = nullptr;
  for (const int i : cell->second) {
    const Distractor& d = distractors_[i];
    if ((point_in_world - d.centre_in_world).squaredNorm() <=
        d.radius_m * d.radius_m) {
      found = &d;
    }
  }
  return found;
}

Eigen::Vector3f DistractorTexture::Albedo(
    const Eigen::Vector3d& point_in_world,
    const Eigen::Vector3d& normal_in_world) const {
  const Distractor* d = At(point_in_world);
  return d != nullptr ? d->albedo
                      : base_->Albedo(point_in_world, normal_in_world);
}

bool DistractorTexture::HasShine() const { return shiny_ || base_->HasShine(); }

Shine DistractorTexture::ShineAt(const Eigen::Vector3d& point_in_world) const {
  const Distractor* d = At(point_in_world);
  return d != nullptr ? d->shine : base_->ShineAt(point_in_world);
}

}  // namespace uw::sim
