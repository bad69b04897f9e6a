// A ControllerCore that forwards to another and records the wall time of each step() (for the
// compute time per controller step that the tools print). Recording allocates only when the
// reserved capacity is exceeded; the wrapped controller's step() is timed as it is.
#pragma once

#include <algorithm>
#include <chrono>
#include <vector>

#include "flagella_control/controller_core.h"

namespace flagella::control {

class TimedController : public ControllerCore {
 public:
  TimedController(ControllerCore& inner, std::size_t expected_steps) : inner_(inner) {
    seconds_.reserve(expected_steps);
  }
  ControllerOutputs step(const ControllerInputs& inputs) override {
    const auto start = std::chrono::steady_clock::now();
    const ControllerOutputs out = inner_.step(inputs);
    seconds_.push_back(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    return out;
  }
  void reset() override { inner_.reset(); }
  const char* name() const override { return inner_.name(); }

  /// The q-quantile (0..1) of the step times so far [s]; 0 without steps.
  double quantile(double q) const {
    if (seconds_.empty()) return 0.0;
    std::vector<double> sorted = seconds_;
    const std::size_t k = std::min(sorted.size() - 1, static_cast<std::size_t>(q * sorted.size()));
    std::nth_element(sorted.begin(), sorted.begin() + k, sorted.end());
    return sorted[k];
  }
  double max() const {
    return seconds_.empty() ? 0.0 : *std::max_element(seconds_.begin(), seconds_.end());
  }
  std::size_t steps() const { return seconds_.size(); }

 private:
  ControllerCore& inner_;
  std::vector<double> seconds_;
};

}  // namespace flagella::control
