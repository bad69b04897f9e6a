// Tests of CommandGate against its contract: in-range values pass, non-finite and out-of-range
// values are rejected while the last valid value is kept, and the failsafe returns the safe
// value exactly when the time since the last *valid* command exceeds the timeout.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "flagella_sim/actuation/command_gate.h"

namespace flagella {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Binary-exact numbers, so that "now - last_time == timeout" holds exactly in floating point.
constexpr double kMin = -2.5;
constexpr double kMax = 7.25;
constexpr double kSafe = 0.5;
constexpr double kTimeout = 0.25;  // [s]
constexpr double kStart = 1.0;     // [s] time of the first command
constexpr double kValue = 3.0;
constexpr double kOtherValue = -1.75;
// A time far beyond any timeout [s].
constexpr double kLongAfter = 1e6;
// Smallest step past a boundary that the gate must notice [s or value units].
constexpr double kEpsilon = 1e-9;

const char kField[] = "motor command omega";
const char kUnit[] = "rad/s";

CommandGateOptions options(double timeout = kTimeout) {
  CommandGateOptions o;
  o.field = kField;
  o.unit = kUnit;
  o.min = kMin;
  o.max = kMax;
  o.safe_value = kSafe;
  o.timeout = timeout;
  return o;
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(CommandGate, OutputIsTheSafeValueBeforeAnyCommand) {
  const CommandGate gate(options());
  EXPECT_FALSE(gate.hasCommand());
  EXPECT_EQ(gate.output(0.0), kSafe);
  EXPECT_EQ(gate.output(kLongAfter), kSafe);
  EXPECT_FALSE(gate.failsafeTripped(kLongAfter));  // nothing to time out
  EXPECT_EQ(gate.acceptedCount(), 0);
  EXPECT_EQ(gate.rejectedCount(), 0);
  EXPECT_TRUE(gate.lastRejection().empty());
}

TEST(CommandGate, AcceptsValuesInsideTheRangeIncludingTheBounds) {
  CommandGate gate(options());
  for (double v : {kValue, kMin, kMax, 0.0, kOtherValue}) {
    SCOPED_TRACE(v);
    EXPECT_EQ(gate.submit(v, kStart), CommandVerdict::Accepted);
    EXPECT_TRUE(gate.hasCommand());
    EXPECT_EQ(gate.output(kStart), v);
  }
  EXPECT_EQ(gate.acceptedCount(), 5);
  EXPECT_EQ(gate.rejectedCount(), 0);
}

TEST(CommandGate, RejectsNonFiniteValuesAndKeepsTheLastValidOne) {
  CommandGate gate(options());
  ASSERT_EQ(gate.submit(kValue, kStart), CommandVerdict::Accepted);
  for (double bad : {kNaN, kInf, -kInf}) {
    SCOPED_TRACE(bad);
    EXPECT_EQ(gate.submit(bad, kStart), CommandVerdict::NotFinite);
    EXPECT_EQ(gate.output(kStart), kValue);
    EXPECT_TRUE(contains(gate.lastRejection(), kField)) << gate.lastRejection();
  }
  EXPECT_EQ(gate.acceptedCount(), 1);
  EXPECT_EQ(gate.rejectedCount(), 3);
}

TEST(CommandGate, NonFiniteBeforeAnyCommandLeavesTheSafeValue) {
  CommandGate gate(options());
  EXPECT_EQ(gate.submit(kNaN, kStart), CommandVerdict::NotFinite);
  EXPECT_FALSE(gate.hasCommand());
  EXPECT_EQ(gate.output(kStart), kSafe);
}

TEST(CommandGate, RejectsOutOfRangeValuesWithAMessageNamingFieldAndBounds) {
  CommandGate gate(options());
  ASSERT_EQ(gate.submit(kValue, kStart), CommandVerdict::Accepted);
  for (double bad : {kMax + kEpsilon, kMin - kEpsilon, 1e12, -1e12}) {
    SCOPED_TRACE(bad);
    EXPECT_EQ(gate.submit(bad, kStart), CommandVerdict::OutOfRange);
    EXPECT_EQ(gate.output(kStart), kValue);
    const std::string& msg = gate.lastRejection();
    EXPECT_TRUE(contains(msg, kField)) << msg;
    EXPECT_TRUE(contains(msg, "-2.5")) << msg;
    EXPECT_TRUE(contains(msg, "7.25")) << msg;
    EXPECT_TRUE(contains(msg, kUnit)) << msg;
  }
  EXPECT_EQ(gate.acceptedCount(), 1);
  EXPECT_EQ(gate.rejectedCount(), 4);
}

TEST(CommandGate, FailsafeTripsOnlyAfterTheTimeout) {
  CommandGate gate(options());
  ASSERT_EQ(gate.submit(kValue, kStart), CommandVerdict::Accepted);
  // now - last = timeout exactly: not yet ("> timeout").
  EXPECT_FALSE(gate.failsafeTripped(kStart + kTimeout));
  EXPECT_EQ(gate.output(kStart + kTimeout), kValue);
  EXPECT_EQ(gate.output(kStart + 0.5 * kTimeout), kValue);
  // Just past it: safe value.
  EXPECT_TRUE(gate.failsafeTripped(kStart + kTimeout + kEpsilon));
  EXPECT_EQ(gate.output(kStart + kTimeout + kEpsilon), kSafe);
  EXPECT_EQ(gate.output(kLongAfter), kSafe);
  EXPECT_TRUE(gate.hasCommand());  // the command is remembered, just not applied
}

TEST(CommandGate, NewValidCommandRestoresTheOutput) {
  CommandGate gate(options());
  ASSERT_EQ(gate.submit(kValue, kStart), CommandVerdict::Accepted);
  const double later = kStart + 2.0 * kTimeout;
  ASSERT_EQ(gate.output(later), kSafe);
  EXPECT_EQ(gate.submit(kOtherValue, later), CommandVerdict::Accepted);
  EXPECT_FALSE(gate.failsafeTripped(later));
  EXPECT_EQ(gate.output(later), kOtherValue);
  EXPECT_EQ(gate.output(later + kTimeout), kOtherValue);
  EXPECT_EQ(gate.output(later + kTimeout + kEpsilon), kSafe);
}

TEST(CommandGate, RejectedCommandsDoNotRefreshTheFailsafeTimer) {
  CommandGate gate(options());
  ASSERT_EQ(gate.submit(kValue, kStart), CommandVerdict::Accepted);
  // A stream of garbage just before the deadline must not keep the output alive.
  const double just_before = kStart + 0.9 * kTimeout;
  EXPECT_EQ(gate.submit(kNaN, just_before), CommandVerdict::NotFinite);
  EXPECT_EQ(gate.submit(kMax + 1.0, just_before), CommandVerdict::OutOfRange);
  EXPECT_EQ(gate.submit(-kInf, just_before), CommandVerdict::NotFinite);
  const double past_deadline = kStart + kTimeout + kEpsilon;
  EXPECT_TRUE(gate.failsafeTripped(past_deadline));
  EXPECT_EQ(gate.output(past_deadline), kSafe);
}

TEST(CommandGate, ZeroTimeoutDisablesTheFailsafe) {
  CommandGate gate(options(0.0));
  ASSERT_EQ(gate.submit(kValue, kStart), CommandVerdict::Accepted);
  EXPECT_FALSE(gate.failsafeTripped(kLongAfter));
  EXPECT_EQ(gate.output(kLongAfter), kValue);
}

TEST(CommandGate, ClearForgetsTheCommand) {
  CommandGate gate(options());
  ASSERT_EQ(gate.submit(kValue, kStart), CommandVerdict::Accepted);
  ASSERT_NE(gate.submit(kNaN, kStart), CommandVerdict::Accepted);
  gate.clear();
  EXPECT_FALSE(gate.hasCommand());
  EXPECT_EQ(gate.acceptedCount(), 0);
  EXPECT_EQ(gate.rejectedCount(), 0);
  EXPECT_TRUE(gate.lastRejection().empty());
  EXPECT_EQ(gate.output(kStart), kSafe);
  EXPECT_FALSE(gate.failsafeTripped(kLongAfter));
  // Works normally afterwards, with a fresh timer.
  const double later = kStart + 10.0 * kTimeout;
  EXPECT_EQ(gate.submit(kOtherValue, later), CommandVerdict::Accepted);
  EXPECT_EQ(gate.output(later + kTimeout), kOtherValue);
  EXPECT_EQ(gate.output(later + kTimeout + kEpsilon), kSafe);
}

TEST(CommandGate, CountersCountEveryVerdict) {
  CommandGate gate(options());
  const double values[] = {kValue, kNaN, kMax + 1.0, kMin, kInf, kMin - 1.0, kMax, -kInf};
  long accepted = 0, rejected = 0;
  for (double v : values) {
    const bool ok = std::isfinite(v) && v >= kMin && v <= kMax;  // the contract, stated directly
    EXPECT_EQ(gate.submit(v, kStart) == CommandVerdict::Accepted, ok) << v;
    (ok ? accepted : rejected)++;
    EXPECT_EQ(gate.acceptedCount(), accepted);
    EXPECT_EQ(gate.rejectedCount(), rejected);
  }
  EXPECT_EQ(accepted, 3);
  EXPECT_EQ(rejected, 5);
}

TEST(CommandGate, DegenerateRangeAcceptsOnlyItsPoint) {
  CommandGateOptions o = options();
  o.min = o.max = o.safe_value = kSafe;
  CommandGate gate(o);
  EXPECT_EQ(gate.submit(kSafe, kStart), CommandVerdict::Accepted);
  EXPECT_EQ(gate.submit(kSafe + kEpsilon, kStart), CommandVerdict::OutOfRange);
}

TEST(CommandGate, InconsistentOptionsThrow) {
  auto expectThrow = [](const CommandGateOptions& o, const char* what) {
    SCOPED_TRACE(what);
    EXPECT_THROW(CommandGate{o}, std::invalid_argument);
  };
  CommandGateOptions o = options();
  o.min = kMax;
  o.max = kMin;
  expectThrow(o, "min > max");
  o = options();
  o.min = kNaN;
  expectThrow(o, "NaN min");
  o = options();
  o.safe_value = kMax + 1.0;
  expectThrow(o, "safe value above max");
  o = options();
  o.safe_value = kMin - 1.0;
  expectThrow(o, "safe value below min");
  o = options();
  o.safe_value = kNaN;
  expectThrow(o, "NaN safe value");
  o = options(-kTimeout);
  expectThrow(o, "negative timeout");
  o = options(kNaN);
  expectThrow(o, "NaN timeout");
  o = options(kInf);
  expectThrow(o, "infinite timeout");
  EXPECT_NO_THROW(CommandGate{options()});
  EXPECT_NO_THROW(CommandGate{options(0.0)});
}

}  // namespace
}  // namespace flagella
