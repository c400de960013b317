// A rock-and-sediment albedo made of hashed 3D value noise, evaluated at the
// surface point itself, so that floors, walls and overhangs are textured
// alike without UV maps or seams.
//
// Three bands of detail, each with its own job:
//  - grain (cm): strong local contrast, the blobs and corners SIFT detects
//    and matches at 1-5 m range with a ~1000 px focal length;
//  - patches (dm): stains and lighter/darker areas that make neighbouring
//    images look different;
//  - regions (m): rock outcrops versus sediment cover.
// The lattice hash has no period within 2^32 cells and every octave is
// rotated differently, so no pattern repeats across the world (a repeat
// would give SIFT false matches between distant places).
//
// The renderer calls Albedo for every sub-pixel sample (~3 M per 1024 x 768
// image), so all eight noise octaves are evaluated at once in SIMD
// registers: about 100 ns per call on one core.
#pragma once

#include <array>
#include <cstdint>

#include <Eigen/Core>

#include "sim/texture.h"

namespace uw::sim {

struct ProceduralTextureOptions {
  // Wavelength of the finest grain octave (m) and the number of grain
  // octaves (1-4), each twice the wavelength of the previous one: 1.5, 3, 6,
  // 12 cm by default.
  double grain_wavelength_m = 0.015;
  int grain_octaves = 4;
  // Relative brightness modulation by the grain, in [0, 1].
  double grain_contrast = 0.55;
  // Wavelengths of the dm-scale patches and the m-scale regions (m); each
  // band has two octaves.
  double patch_wavelength_m = 0.35;
  double region_wavelength_m = 4.0;
  // Relative brightness modulation by the patches, in [0, 1].
  double patch_contrast = 0.3;
  // Fraction of a level floor covered by sediment rather than bare rock, in
  // [0, 1]; slopes steeper than ~40 deg get much less, walls and overhang
  // undersides almost none.
  double sediment_cover = 0.45;
  // Linear RGB albedos in [0, 1].
  std::array<double, 3> rock_albedo = {0.17, 0.19, 0.15};
  std::array<double, 3> sediment_albedo = {0.36, 0.31, 0.22};
  std::array<double, 3> stain_albedo = {0.26, 0.20, 0.11};
  // How far dm-scale stains pull the colour towards stain_albedo, in [0, 1].
  double stain_strength = 0.6;

  void Check() const;  // throws uw::Error naming the offending field
};

namespace internal {

// The texture's eight noise octaves, stored lane by lane so that one Albedo
// call evaluates all of them at once in SIMD registers: lanes 0-3 are the
// grain octaves (finest first), 4-5 the patches, 6-7 the regions. Lattice
// coordinates of a point p in lane i are
// lattice_from_world[.][i] * p + offset[.][i] (a scaled random rotation).
struct NoiseLanes {
  static constexpr int kLanes = 8;
  alignas(32) float lattice_from_world[9][kLanes];  // row-major 3x3
  alignas(32) float offset[3][kLanes];
  alignas(32) uint32_t axis_seed[3][kLanes];
  alignas(32) float weight[kLanes];  // each band sums to unit variance
};

}  // namespace internal

class ProceduralTexture : public Texture {
 public:
  // The same options and seed give the same albedo bit for bit.
  ProceduralTexture(const ProceduralTextureOptions& options, uint64_t seed);

  Eigen::Vector3f Albedo(const Eigen::Vector3d& point_in_world,
                         const Eigen::Vector3d& normal_in_world) const override;

 private:
  ProceduralTextureOptions options_;
  internal::NoiseLanes lanes_;
  Eigen::Vector3f rock_;
  Eigen::Vector3f sediment_;
  Eigen::Vector3f stain_;
  float sediment_threshold_;
  float grain_contrast_;
  float patch_contrast_;
  float stain_strength_;
};

}  // namespace uw::sim
