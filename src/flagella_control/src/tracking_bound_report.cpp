#include "flagella_control/tracking_bound_report.h"

#include <cstdio>
#include <fstream>
#include <stdexcept>

namespace flagella::control {

std::string describeBound(const TrackingBound& bound, double tail_length) {
  if (!bound.best_max.complete) return "bound: no schedule completes the path";
  char text[256];
  std::snprintf(text, sizeof text,
                "bound: max %.1f mm (%.3f l) [schedule of %.0f s], RMS %.1f mm (%.3f l) "
                "[schedule of %.0f s]",
                1e3 * bound.best_max.max_error, bound.best_max.max_error / tail_length,
                bound.best_max.duration, 1e3 * bound.best_rms.rms_error,
                bound.best_rms.rms_error / tail_length, bound.best_rms.duration);
  return text;
}

TrackingBoundOptions refinedOptions(const TrackingBoundOptions& o) {
  TrackingBoundOptions fine = o;
  fine.duty_steps = 2 * o.duty_steps;
  fine.progress_cell = 0.5 * o.progress_cell;
  fine.cross_track_cell = 0.5 * o.cross_track_cell;
  fine.heading_cell = 0.5 * o.heading_cell;
  return fine;
}

void writeBoundJson(const TrackingBound& bound, const std::string& file) {
  std::ofstream out(file);
  if (!out) throw std::runtime_error("cannot write " + file);
  char text[256];
  std::snprintf(text, sizeof text,
                "{\"bound_max_mm\": %.3f, \"bound_rms_mm\": %.3f, \"max_schedule_s\": %.1f, "
                "\"rms_schedule_s\": %.1f}\n",
                1e3 * bound.best_max.max_error, 1e3 * bound.best_rms.rms_error,
                bound.best_max.duration, bound.best_rms.duration);
  out << text;
}

}  // namespace flagella::control
