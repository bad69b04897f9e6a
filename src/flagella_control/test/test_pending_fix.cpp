// The camera fix as every controller shell hands it over (pending_fix.h): only on an IMU sample
// stamped after the fix, once, and never with non-finite coordinates.
#include <gtest/gtest.h>

#include <cmath>

#include "flagella_control/pending_fix.h"

namespace flagella::control {
namespace {

ControllerInputs sampleAt(double t) {
  ControllerInputs in;
  in.time = t;
  in.imu_valid = true;
  return in;
}

TEST(PendingFix, AFixReachesTheFirstSampleStampedAfterItAndOnlyThatOne) {
  PendingFix fix;
  fix.offer(0.01, -0.02, 0.03, 5.0);
  ControllerInputs same = sampleAt(5.0);  // the IMU sample of the fix's own instant
  fix.deliverBefore(same);
  EXPECT_FALSE(same.position_valid);
  ControllerInputs next = sampleAt(5.01);
  fix.deliverBefore(next);
  ASSERT_TRUE(next.position_valid);
  EXPECT_EQ(next.position[0], 0.01);
  EXPECT_EQ(next.position[1], -0.02);
  EXPECT_EQ(next.position[2], 0.03);
  ControllerInputs after = sampleAt(5.02);
  fix.deliverBefore(after);
  EXPECT_FALSE(after.position_valid);
}

TEST(PendingFix, AFixHeardAfterItsSampleIsDeliveredTheSameWay) {
  // Whichever arrives first, the fix taken at 5.0 s reaches the controller at 5.01 s.
  PendingFix fix;
  ControllerInputs same = sampleAt(5.0);
  fix.deliverBefore(same);  // the sample first: nothing pending
  EXPECT_FALSE(same.position_valid);
  fix.offer(0.01, -0.02, 0.03, 5.0);
  ControllerInputs next = sampleAt(5.01);
  fix.deliverBefore(next);
  EXPECT_TRUE(next.position_valid);
}

TEST(PendingFix, NonFiniteCoordinatesAreIgnoredAndAPlanarFixNeedsNoHeight) {
  PendingFix fix;
  fix.offer(NAN, 0.0, 0.0, 1.0);
  fix.offer(0.0, 0.0, INFINITY, 1.0);
  ControllerInputs in = sampleAt(2.0);
  fix.deliverBefore(in);
  EXPECT_FALSE(in.position_valid);
  fix.offer(0.5, 0.25, NAN, 1.0, /*with_height=*/false);
  fix.deliverBefore(in);
  ASSERT_TRUE(in.position_valid);
  EXPECT_EQ(in.position[0], 0.5);
  EXPECT_EQ(in.position[2], 0.0);
}

}  // namespace
}  // namespace flagella::control
