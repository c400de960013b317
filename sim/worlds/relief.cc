#include "sim/worlds/relief.h"

#include "sim/worlds/option_checks.h"

namespace uw::sim {

void ReliefOptions::Check(const std::string& where) const {
  CheckNonNegative(undulation_amplitude_m, where, "undulation_amplitude_m");
  CheckPositive(undulation_wavelength_m, where, "undulation_wavelength_m");
  CheckNonNegative(roughness_amplitude_m, where, "roughness_amplitude_m");
  CheckPositive(roughness_wavelength_m, where, "roughness_wavelength_m");
}

Relief::Relief(const ReliefOptions& options, double vertex_spacing,
               SplitMix64Stream& random)
    : options_(options),
      undulation_(random, options.undulation_wavelength_m,
                  kVerticesPerFinestWavelength * vertex_spacing),
      roughness_(random, options.roughness_wavelength_m,
                 kVerticesPerFinestWavelength * vertex_spacing) {}

double Relief::operator()(const Eigen::Vector3d& p) const {
  return options_.undulation_amplitude_m * undulation_(p) +
         options_.roughness_amplitude_m * roughness_(p);
}

}  // namespace uw::sim
