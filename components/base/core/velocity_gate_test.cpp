// The base's gate: e-stop and staleness decided by the base, whatever the commands say.
#include "base/core/velocity_gate.hpp"

#include <gtest/gtest.h>

#include <limits>

namespace sb = stereoball::base;

namespace {
constexpr int64_t kMs = 1'000'000;
constexpr int64_t kT0 = 1'000'000 * kMs;
}  // namespace

TEST(VelocityGate, DrivesOnlyWhileTheCommandIsFresh) {
  sb::VelocityGate gate({300 * kMs});
  EXPECT_EQ(gate.step(kT0).state, sb::GateState::kNoCommand);
  gate.on_command({0.5, 0.2}, kT0, kT0);
  auto out = gate.step(kT0 + 300 * kMs);  // exactly the timeout: still fresh
  EXPECT_EQ(out.state, sb::GateState::kDriving);
  EXPECT_DOUBLE_EQ(out.velocity.linear_mps, 0.5);
  EXPECT_DOUBLE_EQ(out.velocity.angular_radps, 0.2);
  out = gate.step(kT0 + 300 * kMs + 1);
  EXPECT_EQ(out.state, sb::GateState::kStale);
  EXPECT_EQ(out.velocity.linear_mps, 0.0);
}

TEST(VelocityGate, ACommandThatArrivesLateNeverMovesTheBase) {
  // Given a command stamped 400 ms before it reaches the base (timeout 300 ms)
  sb::VelocityGate gate({300 * kMs});
  gate.on_command({0.5, 0.2}, kT0, kT0 + 400 * kMs);
  // Then it is stale on arrival: its age counts from its stamp, not from its receipt
  const auto out = gate.step(kT0 + 400 * kMs);
  EXPECT_EQ(out.state, sb::GateState::kStale);
  EXPECT_EQ(out.velocity.linear_mps, 0.0);
  EXPECT_EQ(out.velocity.angular_radps, 0.0);
}

TEST(VelocityGate, ADelayedCommandDrivesOnlyForWhatIsLeftOfItsTimeout) {
  // Given a command stamped 200 ms before its receipt
  sb::VelocityGate gate({300 * kMs});
  gate.on_command({0.5, 0.0}, kT0, kT0 + 200 * kMs);
  // Then it drives until its stamp plus the timeout, not its receipt plus the timeout
  EXPECT_EQ(gate.step(kT0 + 300 * kMs).state, sb::GateState::kDriving);
  EXPECT_EQ(gate.step(kT0 + 300 * kMs + 1).state, sb::GateState::kStale);
}

TEST(VelocityGate, AStampAheadOfTheBasesClockBuysNoTime) {
  // Given a command stamped 5 s in the base's future (a sender clock ahead)
  sb::VelocityGate gate({300 * kMs});
  gate.on_command({0.5, 0.0}, kT0 + 5'000 * kMs, kT0);
  // Then it expires at its receipt plus the timeout
  EXPECT_EQ(gate.step(kT0 + 300 * kMs).state, sb::GateState::kDriving);
  EXPECT_EQ(gate.step(kT0 + 300 * kMs + 1).state, sb::GateState::kStale);
}

TEST(VelocityGate, FreshnessRuleSaturatesOnGarbageStamps) {
  constexpr int64_t kMin = std::numeric_limits<int64_t>::min();
  constexpr int64_t kMax = std::numeric_limits<int64_t>::max();
  // A stamp at the bottom of the range is stale at any time without overflowing
  EXPECT_EQ(sb::command_expiry_ns(kMin, kT0, 300 * kMs), kMin + 300 * kMs);
  EXPECT_FALSE(sb::command_fresh(kMin, kT0, kT0, 300 * kMs));
  // A stamp at the top falls back to the receipt
  EXPECT_EQ(sb::command_expiry_ns(kMax, kT0, 300 * kMs), kT0 + 300 * kMs);
  EXPECT_TRUE(sb::command_fresh(kMax, kT0, kT0 + 300 * kMs, 300 * kMs));
  // Both at the top: the sum saturates instead of wrapping into the past
  EXPECT_EQ(sb::command_expiry_ns(kMax, kMax, 300 * kMs), kMax);
}

TEST(VelocityGate, EstopStopsAndIgnoresCommandsUntilReleasedAndCommandedAgain) {
  sb::VelocityGate gate({300 * kMs});
  gate.on_command({0.5, 0.0}, kT0, kT0);
  // When the stop is engaged, then the output is zero and new commands are ignored
  gate.set_estop(true);
  EXPECT_EQ(gate.step(kT0).state, sb::GateState::kEmergencyStop);
  gate.on_command({1.0, 1.0}, kT0 + kMs, kT0 + kMs);
  const auto stopped = gate.step(kT0 + kMs);
  EXPECT_EQ(stopped.state, sb::GateState::kEmergencyStop);
  EXPECT_EQ(stopped.velocity.linear_mps, 0.0);
  EXPECT_EQ(stopped.velocity.angular_radps, 0.0);
  // When released, then the command from before the stop does not resume motion
  gate.set_estop(false);
  EXPECT_EQ(gate.step(kT0 + 2 * kMs).state, sb::GateState::kNoCommand);
  gate.on_command({0.3, 0.0}, kT0 + 3 * kMs, kT0 + 3 * kMs);
  EXPECT_EQ(gate.step(kT0 + 3 * kMs).state, sb::GateState::kDriving);
}

TEST(VelocityGate, NonFiniteCommandsCountAsZero) {
  sb::VelocityGate gate({300 * kMs});
  gate.on_command(
      {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}, kT0,
      kT0);
  const auto out = gate.step(kT0);
  EXPECT_EQ(out.velocity.linear_mps, 0.0);
  EXPECT_EQ(out.velocity.angular_radps, 0.0);
}

TEST(VelocityGate, ParamsValidateNamesTheField) {
  EXPECT_TRUE(sb::VelocityGateParams{}.validate().ok());
  const auto bad = sb::VelocityGateParams{0}.validate();
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().find("command_timeout_ns"), std::string::npos);
}
