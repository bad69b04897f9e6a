#include "flagella_control/lcm_harness.h"

#include <chrono>
#include <stdexcept>

namespace flagella::control {

LcmHarness::LcmHarness(flagella::SimSession& session, ControllerCore& controller,
                       HarnessOptions options)
    : options_(std::move(options)),
      lcm_(options_.lcm_url),
      session_(session),
      sim_shell_(lcm_, session, options_),
      controller_shell_(lcm_, controller, options_.channel_prefix) {
  if (!lcm_.good()) throw std::runtime_error("LCM: cannot open provider " + options_.lcm_url);
}

void LcmHarness::deliverAll() {
  while (lcm_.handleTimeout(0) > 0) {
  }
}

HarnessReport LcmHarness::run(double duration, const std::function<void()>& after_step) {
  HarnessReport report;
  const flagella::LcmChannels channels = flagella::LcmChannels::withPrefix(options_.channel_prefix);
  const auto wall_start = std::chrono::steady_clock::now();
  const double end = session_.time() + duration;
  sim_shell_.publishDue(report.published, true);
  deliverAll();
  stop_requested_ = false;
  while (session_.time() < end - 0.5 * session_.dt() && !stop_requested_) {
    if (!session_.step()) {
      report.halted = true;
      break;
    }
    ++report.steps;
    sim_shell_.publishDue(report.published);
    deliverAll();
    if (after_step) after_step();
  }
  report.sim_time = session_.time();
  report.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  report.received[channels.motor_command] = sim_shell_.motorReceived();
  report.received[channels.slider_command] = sim_shell_.sliderReceived();
  report.received[channels.imu] = controller_shell_.imuReceived();
  report.published[channels.motor_command] = controller_shell_.commandsPublished();
  report.received[channels.camera_fix] = controller_shell_.cameraReceived();
  report.published.emplace(channels.camera_fix, 0);  // listed even when the camera is off
  return report;
}

}  // namespace flagella::control
