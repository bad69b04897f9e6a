// Checks the config overrides that measured data carry (metadata and per-row CSV columns)
// against the baseline config before any model run, so that a bad value is reported with its
// file and row instead of failing deep inside a fit, and no override is silently replaced.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>
#include <utility>
#include <vector>

#include "flagella_identify/data_io.h"

namespace flagella {
namespace identify {

/// What the fit will set in every experiment's config, and so what data may not override.
struct FittedNames {
  std::vector<std::string> parameters;  ///< free baseline parameters ("medium.viscosity")
  /// Candidates the fit may add, each with the config paths it writes (Candidate::writes).
  std::vector<std::pair<std::string, std::vector<std::string>>> candidates;
};

/// The names for a fit of `free` baseline parameters with `candidates` (names; empty = the
/// standard list).
FittedNames fittedNames(const std::vector<std::string>& free,
                        const std::vector<std::string>& candidates);

/// Throws DataError naming the file (and the CSV row of a row override) when an override of the
/// data is refused by the config reader on top of `baseline` (a value out of range, not a number,
/// an unknown field), or names a parameter or candidate effect the fit supplies.
void checkDataOverrides(const MeasuredData& data, const YAML::Node& baseline,
                        const std::string& baseline_source, const FittedNames& fitted);

}  // namespace identify
}  // namespace flagella
