#include "flagella_identify/calibration.h"

#include <algorithm>
#include <stdexcept>

#include "flagella_identify/check_overrides.h"
#include "text_format.h"

namespace flagella {
namespace identify {

Split trainingOnlySplit(const MeasuredData& data) {
  Split split;
  for (const SteadyStateTable& table : data.tables)
    split.table_row_held_out.emplace_back(table.rows.size(), false);
  for (const TimeSeries& s : data.series) split.series_split_time.push_back(s.t.back() + 1.0);
  return split;
}

FitOptions fitOptionsFor(const MeasuredData& data, FitOptions options) {
  for (const SteadyStateTable& table : data.tables)
    for (const SteadyStateRow& row : table.rows)
      if (row.measured.count("buckling_threshold")) {
        options.log_step = std::max(options.log_step, kThresholdLogStep);
        options.function_tolerance =
            std::max(options.function_tolerance, kThresholdFunctionTolerance);
        options.derivative_free = true;
      }
  return options;
}

CalibrationResult calibrate(const MeasuredData& data, const YAML::Node& baseline,
                            const std::string& source, const CalibrationOptions& options) {
  if (options.free.empty())
    throw ConfigError("calibration needs at least one free parameter (--free)");
  checkDataOverrides(data, baseline, source, FittedNames{options.free, {}});
  Model model(baseline, source, options.free);
  const Evaluator evaluator(data, trainingOnlySplit(data), options.evaluator);
  CalibrationResult result;
  result.start = model.parameters();
  if (options.progress)
    options.progress("calibrating " + joined(options.free, ", ") + " on every experiment");
  result.fit = fitModel(model, evaluator, fitOptionsFor(data, options.fit));
  if (!result.fit.ok) throw std::runtime_error("calibration failed: " + result.fit.message);
  result.parameters = model.parameters();
  result.evaluation = evaluator.evaluate(model, model.values(), Part::kAll);
  if (!result.evaluation.ok)
    throw std::runtime_error("the calibrated model cannot be simulated: " +
                             result.evaluation.failure);
  result.quality = diagnose(result.evaluation, data);
  result.calibrated_config = model.extendedConfig();
  return result;
}

}  // namespace identify
}  // namespace flagella
