// The path-following controller factory: mode name -> controller core (path_controller_factory.h).
#include "flagella_control/path_controller_factory.h"

#include <stdexcept>

namespace flagella::control {

const std::vector<std::string>& pathControllerModes() {
  static const std::vector<std::string> modes = {"receding_horizon", "closed_loop", "open_loop"};
  return modes;
}

void requirePathControllerMode(const std::string& mode, const std::string& field) {
  const std::vector<std::string>& modes = pathControllerModes();
  for (const std::string& known : modes)
    if (mode == known) return;
  // "'a', 'b' or 'c'"
  std::string allowed;
  for (std::size_t i = 0; i < modes.size(); ++i) {
    if (i > 0) allowed += i + 1 == modes.size() ? " or " : ", ";
    allowed += "'" + modes[i] + "'";
  }
  throw std::invalid_argument(field + " must be " + allowed + ", got '" + mode + "'");
}

std::unique_ptr<PathControllerBase> makePathController(PathSpec spec, BinaryCalibration calibration,
                                                       const PathControllerOptions& options) {
  requirePathControllerMode(options.mode);
  if (options.mode == "open_loop")
    return std::make_unique<ScheduleController>(std::move(spec), std::move(calibration));
  if (options.mode == "receding_horizon")
    return std::make_unique<RecedingHorizonController>(std::move(spec), std::move(calibration),
                                                       options.horizon_gains, options.gains);
  return std::make_unique<PathFollowingController>(std::move(spec), std::move(calibration),
                                                   options.gains);
}

}  // namespace flagella::control
