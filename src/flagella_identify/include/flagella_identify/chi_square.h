// Chi-square critical values at the tool's significance level, p = 1e-3 (docs/model.md 7.6).
#pragma once

namespace flagella {
namespace identify {

/// Chi-square critical value at p = 1e-3 for k degrees of freedom (k >= 1).
double chiSquareCritical(int k);

}  // namespace identify
}  // namespace flagella
