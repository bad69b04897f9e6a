// Calibration alone (docs/model.md 8.4.5, the source's workflow for the helical robot): fit the
// free config parameters on every experiment of a data set (no held-out split, no candidate
// effects), e.g. the RSS regularisation eps_ratio from a gimbal buckling-threshold table, then
// C_t and C_r of the head drag from an untethered speed and head-rate table.
#pragma once

#include <yaml-cpp/yaml.h>

#include <functional>
#include <string>
#include <vector>

#include "flagella_identify/diagnosis.h"
#include "flagella_identify/fit.h"

namespace flagella {
namespace identify {

/// Finite-difference step of log-scale parameters when the data hold buckling thresholds: a
/// model threshold is searched on a 2 % rate grid and interpolated, and scatters by 1-2 % near
/// the criterion, so smaller steps would difference that scatter rather than the model.
constexpr double kThresholdLogStep = 0.05;
/// Relative change of the cost that ends a fit on thresholds: the model's threshold scatters by
/// 1-2 % near the criterion (docs/model.md 8.4.4), so finer changes are that scatter.
constexpr double kThresholdFunctionTolerance = 1e-2;

struct CalibrationOptions {
  std::vector<std::string> free;  ///< config paths to fit (log scale, within x20 and their range)
  EvaluatorOptions evaluator;
  FitOptions fit;
  std::function<void(const std::string&)> progress;
};

struct CalibrationResult {
  FitResult fit;
  std::vector<FitParameter> start;       ///< the free parameters at their start values
  std::vector<FitParameter> parameters;  ///< fitted, with one-sigma uncertainties
  Evaluation evaluation;                 ///< every experiment at the fitted values
  Diagnosis quality;                     ///< chi^2, RMS z and errors per output at the optimum
  YAML::Node calibrated_config;          ///< the baseline with the fitted values
};

/// A split that holds nothing out (every experiment trains).
Split trainingOnlySplit(const MeasuredData& data);

/// `options` with the method, finite-difference step and stopping rule the data need: for
/// thresholds a derivative-free search for one free parameter (FitOptions::derivative_free),
/// kThresholdLogStep (also the step of the uncertainty's Jacobian) and
/// kThresholdFunctionTolerance.
FitOptions fitOptionsFor(const MeasuredData& data, FitOptions options);

/// Fits `options.free` of `baseline` (read from `source`) on all of `data`. Throws ConfigError
/// for a bad free parameter, std::runtime_error when the model cannot be simulated or the fit
/// gives no usable solution.
CalibrationResult calibrate(const MeasuredData& data, const YAML::Node& baseline,
                            const std::string& source, const CalibrationOptions& options);

/// Writes calibration.json (parameters, fit quality, every experiment's data and model value),
/// calibration.md and calibrated_config.yaml into `directory`; returns their paths.
std::vector<std::string> writeCalibrationReport(const CalibrationResult& result,
                                                const MeasuredData& data,
                                                const std::vector<std::string>& data_files,
                                                const std::string& baseline_config,
                                                const std::string& directory);

}  // namespace identify
}  // namespace flagella
