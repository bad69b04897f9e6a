// The surrounding medium: bulk viscosity (or granular RFT coefficient), density, gravity and
// an optional depth-dependent viscosity near an air-liquid interface (docs/model.md 2, 3.3).
#pragma once

#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/core/types.h"

namespace flagella {

/// mu(y) = mu0 / (1 + exp(k (y - h)/R)), y = height above the reference level (docs/model.md 3.3,
/// Eq. 4.7).
struct InterfaceViscosityProfile {
  bool enabled = false;
  double reference_height = 0.0;  ///< world height of the head axis at rest [m]
  double onset_height = 0.0;      ///< h: height above the reference where mixing begins [m]
  double sharpness = 20.0;        ///< k (dimensionless)
  double length_scale = 0.016;    ///< R: head radius used to scale heights [m]

  /// mu(y)/mu0 at world height `height`; 1 when disabled.
  double factor(double height) const;
  /// d(mu/mu0)/d(height).
  double factorDerivative(double height) const;
};

class Medium {
 public:
  Medium();
  ParameterSet& parameters() { return params_; }
  const ParameterSet& parameters() const { return params_; }
  /// mu0 [Pa s], the configured bulk viscosity. A time-varying viscosity (viscosity_drift) is
  /// effect-owned state: effects read the current value from EffectContext::viscosity.
  double viscosity() const { return params_[viscosity_]; }
  double density() const { return params_[density_]; }  ///< rho_m [kg/m^3]

  Vec3 up = Vec3::UnitZ();               ///< unit world vertical, from liquid into air
  Vec3 gravity = Vec3(0.0, 0.0, -9.81);  ///< [m/s^2]
  InterfaceViscosityProfile profile;

 private:
  ParameterSet params_;
  int viscosity_ = 0;
  int density_ = 0;
};

}  // namespace flagella
