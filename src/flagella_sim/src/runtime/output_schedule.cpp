// The output schedule shared by the ROS node and the LCM shell: which outputs are due when.
#include "flagella_sim/runtime/output_schedule.h"

#include <utility>

#include "flagella_sim/runtime/sim_session.h"

namespace flagella {

OutputRates OutputRates::forSession(const SessionOptions& session, double state_rate) {
  OutputRates r;
  r.rod_state = state_rate;
  r.imu = session.imu.rate;
  if (session.camera.enabled()) r.camera_fix = session.camera.rate;
  return r;
}

OutputSchedule::OutputSchedule(const OutputRates& rates) {
  const std::pair<Output, std::optional<double>> all[] = {{Output::RodState, rates.rod_state},
                                                          {Output::Markers, rates.markers},
                                                          {Output::Path, rates.path},
                                                          {Output::CameraFix, rates.camera_fix},
                                                          {Output::Imu, rates.imu},
                                                          {Output::Diagnostics, rates.diagnostics}};
  for (const auto& [output, rate] : all)
    if (rate) slot(output).emplace(*rate);
}

bool OutputSchedule::ask(Output output, double time, bool force) {
  std::optional<RateSchedule>& s = slot(output);
  if (!s) return false;
  return s->due(time) || force;  // asked even when forced: the schedule stays anchored
}

DueOutputs OutputSchedule::due(double time, bool force) {
  DueOutputs d;
  d.rod_state = ask(Output::RodState, time, force);
  d.markers = ask(Output::Markers, time, force);
  d.path = ask(Output::Path, time, force);
  d.camera_fix = ask(Output::CameraFix, time, force);
  d.imu = ask(Output::Imu, time, force);
  return d;
}

bool OutputSchedule::diagnosticsDue(double time) { return ask(Output::Diagnostics, time, false); }

void OutputSchedule::restart() {
  for (std::size_t i = 0; i < kOutputs; ++i)
    if (schedules_[i] && i != static_cast<std::size_t>(Output::Diagnostics))
      schedules_[i]->restart();
}

}  // namespace flagella
