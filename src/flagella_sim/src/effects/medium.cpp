#include "flagella_sim/effects/medium.h"

#include <cmath>

namespace flagella {

double InterfaceViscosityProfile::factor(double height) const {
  if (!enabled) return 1.0;
  const double y = height - reference_height;
  return 1.0 /
         (1.0 + std::exp(sharpness * (y - onset_height) / length_scale));  // docs/model.md 3.3
}

double InterfaceViscosityProfile::factorDerivative(double height) const {
  if (!enabled) return 0.0;
  const double f = factor(height);
  return -f * (1.0 - f) * sharpness / length_scale;
}

Medium::Medium() {
  viscosity_ = params_.declare("viscosity", 1.0, 0.0, 1e6, "Pa s",
                               "bulk viscosity mu0, or the fitted granular RFT coefficient mu");
  density_ = params_.declare("density", 1000.0, 0.0, 1e5, "kg/m^3", "medium density rho_m");
}

}  // namespace flagella
