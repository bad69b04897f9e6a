#include "flagella_control/lcm_harness.h"

#include <chrono>
#include <stdexcept>

namespace flagella_control {

// ---- simulator side -------------------------------------------------------------------------
SimLcmShell::SimLcmShell(lcm::LCM& lcm, flagella::SimSession& session,
                         const HarnessOptions& options)
    : lcm_(lcm),
      session_(session),
      options_(options),
      channels_(LcmChannels::withPrefix(options.channel_prefix)),
      state_schedule_(options.state_rate),
      imu_schedule_(session.options().imu.rate),
      camera_schedule_(session.options().camera.rate) {
  lcm_.subscribe(channels_.motor_command, &SimLcmShell::onMotorCommand, this);
  lcm_.subscribe(channels_.slider_command, &SimLcmShell::onSliderCommand, this);
}

void SimLcmShell::onMotorCommand(const lcm::ReceiveBuffer*, const std::string&,
                                 const flagella_lcm::motor_command_t* msg) {
  ++motor_received_;
  session_.commandMotor(msg->omega);  // the gate rejects and counts bad values
}

void SimLcmShell::onSliderCommand(const lcm::ReceiveBuffer*, const std::string&,
                                  const flagella_lcm::slider_command_t* msg) {
  ++slider_received_;
  session_.commandSlider(msg->position);
}

void SimLcmShell::publishDue(HarnessReport& report, bool force) {
  const double t = session_.time();
  if (state_schedule_.due(t) || force) {
    const flagella::RodSnapshot snapshot = session_.snapshot();
    if (snapshot.allFinite()) {
      const flagella_lcm::rod_state_t msg =
          flagella::toRodStateMessage(snapshot, options_.world_frame);
      lcm_.publish(channels_.rod_state, &msg);
      ++report.published[channels_.rod_state];
    }
  }
  // The camera fix before the IMU sample of the same instant, so the controller step on that
  // sample already has it. Rate 0: off; none inside the dropout window.
  if (session_.options().camera.enabled() && (camera_schedule_.due(t) || force) &&
      session_.cameraAvailable()) {
    const flagella::CameraFix fix = session_.measureCamera();
    if (fix.position.allFinite()) {
      const flagella_lcm::point_stamped_t msg =
          flagella::toCameraFixMessage(fix, options_.world_frame);
      lcm_.publish(channels_.camera_fix, &msg);
      ++report.published[channels_.camera_fix];
    }
  }
  if (imu_schedule_.due(t) || force) {
    const flagella_lcm::imu_t msg =
        flagella::toImuMessage(session_.measureImu(), options_.imu_frame);
    lcm_.publish(channels_.imu, &msg);
    ++report.published[channels_.imu];
  }
}

// ---- controller side ------------------------------------------------------------------------
ControllerLcmShell::ControllerLcmShell(lcm::LCM& lcm, ControllerCore& controller,
                                       const HarnessOptions& options)
    : lcm_(lcm),
      controller_(controller),
      options_(options),
      channels_(LcmChannels::withPrefix(options.channel_prefix)) {
  lcm_.subscribe(channels_.imu, &ControllerLcmShell::onImu, this);
  lcm_.subscribe(channels_.camera_fix, &ControllerLcmShell::onCameraFix, this);
}

void ControllerLcmShell::onCameraFix(const lcm::ReceiveBuffer*, const std::string&,
                                     const flagella_lcm::point_stamped_t* msg) {
  ++camera_received_;
  fix_pending_ = true;
  fix_position_[0] = msg->point.x;
  fix_position_[1] = msg->point.y;
}

void ControllerLcmShell::onImu(const lcm::ReceiveBuffer*, const std::string&,
                               const flagella_lcm::imu_t* msg) {
  ++imu_received_;
  inputs_.time = flagella::stampSeconds(msg->header);
  inputs_.imu_valid = true;
  inputs_.orientation[0] = msg->orientation.x;
  inputs_.orientation[1] = msg->orientation.y;
  inputs_.orientation[2] = msg->orientation.z;
  inputs_.orientation[3] = msg->orientation.w;
  inputs_.angular_velocity[0] = msg->angular_velocity.x;
  inputs_.angular_velocity[1] = msg->angular_velocity.y;
  inputs_.angular_velocity[2] = msg->angular_velocity.z;
  // The latest camera fix, on this step only.
  inputs_.position_valid = fix_pending_;
  if (fix_pending_) {
    inputs_.position[0] = fix_position_[0];
    inputs_.position[1] = fix_position_[1];
    fix_pending_ = false;
  }
  last_ = controller_.step(inputs_);
  inputs_.position_valid = false;
  flagella_lcm::motor_command_t command;
  command.header = flagella::lcmHeader(inputs_.time, "");
  command.omega = last_.motor_command;
  lcm_.publish(channels_.motor_command, &command);
  ++commands_published_;
  if (last_.slider_valid) {
    flagella_lcm::slider_command_t slider;
    slider.header = command.header;
    slider.position = last_.slider_position;
    lcm_.publish(channels_.slider_command, &slider);
  }
}

// ---- the harness ----------------------------------------------------------------------------
LcmHarness::LcmHarness(flagella::SimSession& session, ControllerCore& controller,
                       HarnessOptions options)
    : options_(std::move(options)),
      lcm_(options_.lcm_url),
      session_(session),
      sim_shell_(lcm_, session, options_),
      controller_shell_(lcm_, controller, options_) {
  if (!lcm_.good()) throw std::runtime_error("LCM: cannot open provider " + options_.lcm_url);
}

void LcmHarness::deliverAll() {
  while (lcm_.handleTimeout(0) > 0) {
  }
}

HarnessReport LcmHarness::run(double duration, const std::function<void()>& after_step) {
  HarnessReport report;
  const LcmChannels channels = LcmChannels::withPrefix(options_.channel_prefix);
  const auto wall_start = std::chrono::steady_clock::now();
  const double end = session_.time() + duration;
  sim_shell_.publishDue(report, true);
  deliverAll();
  stop_requested_ = false;
  while (session_.time() < end - 0.5 * session_.dt() && !stop_requested_) {
    if (!session_.step()) {
      report.halted = true;
      break;
    }
    ++report.steps;
    sim_shell_.publishDue(report);
    deliverAll();
    if (after_step) after_step();
  }
  report.sim_time = session_.time();
  report.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  report.received[channels.motor_command] = sim_shell_.motor_received_;
  report.received[channels.slider_command] = sim_shell_.slider_received_;
  report.received[channels.imu] = controller_shell_.imuReceived();
  report.published[channels.motor_command] = controller_shell_.commandsPublished();
  report.received[channels.camera_fix] = controller_shell_.cameraReceived();
  report.published.emplace(channels.camera_fix, 0);  // listed even when the camera is off
  return report;
}

}  // namespace flagella_control
