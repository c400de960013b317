// Bright things that are not a laser's spot, for the spot detector: shells
// (white discs), debris (fragments of strong colours) and shiny objects
// whose highlight (a glint of the lamp) moves with the camera. They are a
// texture over any world's: an albedo, and a specular lobe that the
// renderer adds to its Lambertian term (sim/renderer.h).
#pragma once

#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json_fwd.hpp>

#include "common/mesh/mesh.h"
#include "sim/texture.h"

namespace uw::sim {

// One object lying on the surface: where a surface point lies within
// radius_m of its centre, the surface has its albedo and shine.
struct Distractor {
  Eigen::Vector3d centre_in_world = Eigen::Vector3d::Zero();
  double radius_m = 0.02;
  Eigen::Vector3f albedo{0.9f, 0.9f, 0.9f};  // linear RGB
  Shine shine;
};

// A white shell (albedo 0.9), a debris fragment of colour `albedo`, and a
// shiny object: grey, with a highlight as bright as white paper at its
// peak, of Blinn-Phong exponent 50 (its half vector within ~12 deg of the
// normal: a glint of a few millimetres on a pebble or a bottle).
Distractor Shell(const Eigen::Vector3d& centre, double radius_m);
Distractor Debris(const Eigen::Vector3d& centre, double radius_m,
                  const Eigen::Vector3f& albedo);
Distractor ShinyObject(const Eigen::Vector3d& centre, double radius_m);

// The debris colours (linear RGB): yellow, green, blue, orange-brown,
// off-white.
const std::vector<Eigen::Vector3f>& DebrisColours();

// Distractors scattered on a world's mesh, for uwsim scenes.
struct DistractorOptions {
  double shells_per_m2 = 0.0;
  double debris_per_m2 = 0.0;
  double shiny_per_m2 = 0.0;
  double min_radius_m = 0.01;
  double max_radius_m = 0.03;

  bool Any() const {
    return shells_per_m2 > 0.0 || debris_per_m2 > 0.0 || shiny_per_m2 > 0.0;
  }
  void Check() const;  // throws uw::Error naming the field
};
void to_json(nlohmann::json& json, const DistractorOptions& options);
void from_json(const nlohmann::json& json, DistractorOptions& options);

// Uniformly over the mesh's area (the counts are density x area, rounded),
// radii uniform in [min, max], debris of DebrisColours(); deterministic for
// a seed.
std::vector<Distractor> ScatterDistractors(const TriangleMesh& mesh,
                                           const DistractorOptions& options,
                                           uint64_t seed);

// `base` with the distractors laid over it.
class DistractorTexture : public Texture {
 public:
  DistractorTexture(std::shared_ptr<const Texture> base,
                    std::vector<Distractor> distractors);

  Eigen::Vector3f Albedo(const Eigen::Vector3d& point_in_world,
                         const Eigen::Vector3d& normal_in_world) const override;
  bool HasShine() const override;
  Shine ShineAt(const Eigen::Vector3d& point_in_world) const override;

 private:
  // The distractor covering the point, or null.
  const Distractor* At(const Eigen::Vector3d& point_in_world) const;

  std::shared_ptr<const Texture> base_;
  std::vector<Distractor> distractors_;
  bool shiny_ = false;
  // A hash grid of cells of cell_m: each distractor is listed in every
  // cell its sphere reaches, so a point looks in its own cell only.
  double cell_m_ = 1.0;
  std::unordered_map<uint64_t, std::vector<int>> cells_;
};

}  // namespace uw::sim
