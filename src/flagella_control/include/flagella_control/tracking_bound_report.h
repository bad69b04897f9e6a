// How the tracking bound is printed beside a tracking result and stored (JSON).
#pragma once

#include <string>

#include "flagella_control/tracking_bound.h"

namespace flagella::control {

/// "bound: max 21.3 mm (0.19 l), RMS 8.1 mm (0.07 l)" with the schedules' durations.
std::string describeBound(const TrackingBound& bound, double tail_length);
/// The options on a grid twice as fine (duty steps doubled, cells halved): the refinement check.
TrackingBoundOptions refinedOptions(const TrackingBoundOptions& options);
/// {"bound_max_mm":..., "bound_rms_mm":..., "max_schedule_s":..., "rms_schedule_s":...}
void writeBoundJson(const TrackingBound& bound, const std::string& file);

}  // namespace flagella::control
