// JSON of fitted parameters and of a diagnosis, shared by the discovery report and the
// calibration report (library-internal).
#pragma once

#include <nlohmann/json.hpp>
#include <vector>

#include "flagella_identify/diagnosis.h"
#include "flagella_identify/fit_parameter.h"

namespace flagella {
namespace identify {

/// A number, or null when it is not finite (JSON has no NaN).
nlohmann::json finiteOrNull(double v);
/// Name, value, uncertainty, unit, range and scale of each parameter.
nlohmann::json parametersJson(const std::vector<FitParameter>& ps);
/// Counts, chi^2, per-output statistics, groups and signatures.
nlohmann::json diagnosisJson(const Diagnosis& d);

}  // namespace identify
}  // namespace flagella
