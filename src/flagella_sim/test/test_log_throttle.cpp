// LogThrottle (runtime/log_throttle.h): the first line passes, then one per period, and each
// line written reports how many were held back since the previous one.
#include <gtest/gtest.h>

#include "flagella_sim/runtime/log_throttle.h"

namespace flagella {
namespace {

TEST(LogThrottle, OneLinePerPeriodCountingTheRest) {
  LogThrottle log(2.0);
  long held = -1;
  EXPECT_TRUE(log.allow(10.0, held));
  EXPECT_EQ(held, 0);
  // A flood: 7828 lines in 13 s (the figure) at a steady rate.
  long written = 1, refused = 0, reported = 0;
  const int lines = 7828;
  for (int k = 1; k <= lines; ++k) {
    if (log.allow(10.0 + 13.0 * k / lines, held)) {
      ++written;
      reported += held;
    } else {
      ++refused;
      EXPECT_EQ(held, 0);
    }
  }
  EXPECT_EQ(written, 7);  // t = 10, 12, ..., 22
  // Every refused line is reported by a later line or is still held.
  EXPECT_TRUE(log.allow(100.0, held));
  EXPECT_EQ(reported + held, refused);
}

TEST(LogThrottle, QuietPeriodsPassAtOnce) {
  LogThrottle log(1.0);
  long held = 0;
  EXPECT_TRUE(log.allow(0.0, held));
  EXPECT_FALSE(log.allow(0.5, held));
  EXPECT_TRUE(log.allow(1.0, held));
  EXPECT_EQ(held, 1);
  EXPECT_TRUE(log.allow(5.0, held));
  EXPECT_EQ(held, 0);
}

}  // namespace
}  // namespace flagella
