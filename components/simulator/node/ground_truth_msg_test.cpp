#include "simulator/node/ground_truth_msg.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace stereoball::simulator {
namespace {

TEST(MsgConversion, CommandAgeIsScaledIntoSimulatedTime) {
  // Given a command stamped 100 ms before now on the wall clock
  stereoball_msg_VelocityCommand msg{};
  msg.stamp_ns = 1'000'000'000;
  msg.linear_mps = 0.3;
  msg.angular_radps = -0.2;
  // When converted at simulated time 5 s running at half speed
  const VelocityCommand c = command_from_msg(msg, 1'100'000'000, 5'000'000'000, 0.5);
  // Then it is 50 ms old in simulated time and keeps its velocities
  EXPECT_EQ(c.stamp_ns, 5'000'000'000 - 50'000'000);
  EXPECT_DOUBLE_EQ(c.linear_mps, 0.3);
  EXPECT_DOUBLE_EQ(c.angular_radps, -0.2);
  // And a command from the future is treated as brand new, a NaN speed as zero
  msg.stamp_ns = 2'000'000'000;
  msg.linear_mps = std::nan("");
  const VelocityCommand f = command_from_msg(msg, 1'100'000'000, 5'000'000'000, 0.5);
  EXPECT_EQ(f.stamp_ns, 5'000'000'000);
  EXPECT_EQ(f.linear_mps, 0.0);
}

TEST(MsgConversion, ExtremeCommandStampsSaturateInsteadOfOverflowing) {
  // Given stamps at both ends of int64 (the fuzzer's INT64_MIN overflowed the age)
  stereoball_msg_VelocityCommand msg{};
  for (const int64_t stamp : {std::numeric_limits<int64_t>::min(), int64_t{0}}) {
    msg.stamp_ns = stamp;
    // When converted
    const VelocityCommand c = command_from_msg(msg, 4'075'323'971'113'178'978, 5'000'000'000, 1.0);
    // Then the age is capped at 60 s of simulated time
    EXPECT_EQ(c.stamp_ns, 5'000'000'000 - 60'000'000'000) << stamp;
  }
  msg.stamp_ns = std::numeric_limits<int64_t>::max();
  EXPECT_EQ(command_from_msg(msg, -5, 7, 1.0).stamp_ns, 7);  // from the future: brand new
  // And a rate that is not a positive number (never configured, but the fuzzer tries) counts
  // as real time, a huge one is capped, the simulated clock's own minimum saturates
  msg.stamp_ns = 0;
  EXPECT_EQ(command_from_msg(msg, 1'000, 5'000, std::nan("")).stamp_ns, 4'000);
  EXPECT_EQ(command_from_msg(msg, 1'000, 5'000, 1e300).stamp_ns, 5'000 - 1'000'000);
  EXPECT_EQ(command_from_msg(msg, 1'000, std::numeric_limits<int64_t>::min(), 1.0).stamp_ns,
            std::numeric_limits<int64_t>::min());
}

}  // namespace
}  // namespace stereoball::simulator
