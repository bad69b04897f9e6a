// Test helper for the LCM bridge test (test/lcm_bridge.sh), working on LCM log files:
//   lcm_log_probe write-commands LOG OMEGA COUNT PERIOD   motor commands for the bridge to play
//   lcm_log_probe check LOG OMEGA                         what the bridge mirrored from ROS
// `check` exits non-zero unless the log holds decodable, finite rod states and IMU samples,
// some rod state shows the commanded motor rate (the command went LCM -> ROS -> simulator and
// the state came back ROS -> LCM) and a later one shows the motor stopped (failsafe).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <flagella_lcm/imu_t.hpp>
#include <flagella_lcm/motor_command_t.hpp>
#include <flagella_lcm/rod_state_t.hpp>
#include <lcm/lcm-cpp.hpp>
#include <string>

#include "flagella_sim/lcm_io/lcm_messages.h"

namespace {

const flagella::LcmChannels kChannels = flagella::LcmChannels::withPrefix("FLAGELLA_");
constexpr int64_t kMicroseconds = 1000000;

int writeCommands(const char* path, double omega, int count, double period) {
  lcm::LogFile log(path, "w");
  if (!log.good()) return std::fprintf(stderr, "cannot write %s\n", path), 1;
  for (int k = 0; k < count; ++k) {
    flagella_lcm::motor_command_t command;
    command.header = flagella::lcmHeader(k * period, "");
    command.omega = omega;
    std::string bytes(command.getEncodedSize(), '\0');
    command.encode(&bytes[0], 0, static_cast<int>(bytes.size()));
    lcm::LogEvent event;
    event.eventnum = k;
    event.timestamp = static_cast<int64_t>(k * period * kMicroseconds);
    event.channel = kChannels.motor_command;
    event.datalen = static_cast<int32_t>(bytes.size());
    event.data = &bytes[0];
    if (log.writeEvent(&event) != 0) return std::fprintf(stderr, "write failed\n"), 1;
  }
  return 0;
}

bool finite(const flagella_lcm::rod_state_t& s) {
  for (const auto& p : s.nodes)
    if (!std::isfinite(p.x + p.y + p.z)) return false;
  return std::isfinite(s.omega_h + s.omega_t + s.omega_motor);
}

int check(const char* path, double omega) {
  lcm::LogFile log(path, "r");
  if (!log.good()) return std::fprintf(stderr, "FAIL: cannot read %s\n", path), 1;
  long states = 0, imus = 0, bad = 0;
  double first_commanded = -1.0, stopped_after = -1.0;
  while (const lcm::LogEvent* event = log.readNextEvent()) {
    if (event->channel == kChannels.rod_state) {
      flagella_lcm::rod_state_t s;
      if (s.decode(event->data, 0, event->datalen) < 0 || !finite(s) || s.num_nodes == 0) {
        ++bad;
        continue;
      }
      ++states;
      const double t = flagella::stampSeconds(s.header);
      if (s.omega_motor == omega && first_commanded < 0) first_commanded = t;
      if (first_commanded >= 0 && s.omega_motor == 0.0 && stopped_after < 0) stopped_after = t;
    } else if (event->channel == kChannels.imu) {
      flagella_lcm::imu_t m;
      if (m.decode(event->data, 0, event->datalen) < 0)
        ++bad;
      else
        ++imus;
    }
  }
  std::printf("LCM log: %ld rod states, %ld IMU samples, %ld undecodable or non-finite\n", states,
              imus, bad);
  std::printf("motor at %.3f rad/s from t = %.2f s, stopped again at t = %.2f s\n", omega,
              first_commanded, stopped_after);
  const bool ok = states > 0 && imus > 0 && bad == 0 && first_commanded >= 0 && stopped_after > 0;
  std::printf("%s\n", ok ? "PASS" : "FAIL");
  return ok ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "";
  if (mode == "write-commands" && argc == 6)
    return writeCommands(argv[2], std::atof(argv[3]), std::atoi(argv[4]), std::atof(argv[5]));
  if (mode == "check" && argc == 4) return check(argv[2], std::atof(argv[3]));
  std::fprintf(stderr,
               "usage: lcm_log_probe write-commands LOG OMEGA COUNT PERIOD | check LOG OMEGA\n");
  return 2;
}
