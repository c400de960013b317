// Relief: the height (or the displacement along the normal) of a rough
// natural surface, as two bands of fBm.
#pragma once

#include <string>

#include <Eigen/Core>

#include "common/util/random.h"
#include "sim/worlds/noise.h"

namespace uw::sim {

// Relief octaves stop at this many vertex spacings per wavelength: finer
// relief would alias on the mesh.
constexpr double kVerticesPerFinestWavelength = 4.0;

// Relief as two bands of fractal (fBm) gradient noise: metre-scale
// undulation and dm-scale roughness. Each band's octaves halve in
// wavelength and amplitude down to four vertex spacings (finer relief would
// not be resolved by the mesh; the texture carries it). Amplitudes are the
// bands' standard deviations.
struct ReliefOptions {
  double undulation_amplitude_m = 0.3;
  double undulation_wavelength_m = 8.0;
  double roughness_amplitude_m = 0.04;
  double roughness_wavelength_m = 0.6;

  // `where` names the section in messages ("seafloor.relief").
  void Check(const std::string& where) const;
};

// Height (or displacement) of a surface: undulation plus roughness.
class Relief {
 public:
  Relief(const ReliefOptions& options, double vertex_spacing,
         SplitMix64Stream& random);

  double operator()(const Eigen::Vector3d& p) const;

 private:
  ReliefOptions options_;
  Fbm undulation_;
  Fbm roughness_;
};

}  // namespace uw::sim
