#include "motion_controller/core/motion_controller.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace stereoball::motion_controller {
namespace {

constexpr std::int64_t kTickNs = 50'000'000;  // 20 Hz
constexpr std::int64_t kT0 = 1'700'000'000'000'000'000;

TrackSample following(double bearing_rad, double distance_m, std::int64_t stamp_ns) {
  TrackSample t;
  t.state = TrackState::kFollowing;
  t.position_valid = true;
  t.bearing_rad = bearing_rad;
  t.distance_m = distance_m;
  t.last_seen_side = bearing_rad > 0 ? Side::kRight : Side::kLeft;
  t.capture_stamp_ns = stamp_ns;
  t.last_accepted_stamp_ns = stamp_ns;
  return t;
}

TrackSample with_state(TrackState s, Side side, std::int64_t stamp_ns) {
  TrackSample t;
  t.state = s;
  t.last_seen_side = side;
  t.capture_stamp_ns = stamp_ns;
  t.last_accepted_stamp_ns = stamp_ns;
  return t;
}

// Parameters with the camera on the robot's centre, so bearings are the robot's.
MotionControllerParams centred() {
  MotionControllerParams p;
  p.camera_right_offset_m = 0.0;
  p.camera_forward_offset_m = 0.0;
  p.bearing_rate_feedforward = 0.0;
  p.distance_rate_feedforward = 0.0;
  return p;
}

// The linear acceleration limit between two commands: braking while the speed drops.
double linear_accel_bound(const MotionControllerParams& p, double v_prev, double v) {
  const bool slowing = std::abs(v) < std::abs(v_prev) || v * v_prev < 0.0;
  return slowing ? std::max(p.max_linear_brake_mps2, p.max_linear_accel_mps2)
                 : p.max_linear_accel_mps2;
}

// A controller ticking at 20 Hz; every tick may deliver a fresh track first.
class Harness {
 public:
  explicit Harness(const MotionControllerParams& p = centred()) : c_(p) {}
  Command tick() {
    now_ += kTickNs;
    return c_.step(now_);
  }
  // A fresh frame every tick: the sample is moved to the tick time, keeping how long before
  // its capture the last accepted position was.
  Command tick(const TrackSample& t) {
    now_ += kTickNs;
    TrackSample fresh = t;
    fresh.last_accepted_stamp_ns = now_ - (t.capture_stamp_ns - t.last_accepted_stamp_ns);
    fresh.capture_stamp_ns = now_;
    const auto response = c_.on_track(fresh, now_);
    EXPECT_TRUE(response.command.has_value());
    return response.command.value_or(Command{});
  }
  Command run(const TrackSample& t, int ticks) {
    Command c;
    for (int i = 0; i < ticks; ++i) c = tick(t);
    return c;
  }
  MotionController& controller() { return c_; }
  std::int64_t now() const { return now_; }

 private:
  MotionController c_;
  std::int64_t now_ = kT0;
};

TEST(MotionController, GivenNoTrackYet_ThenZeroAndWaiting) {
  Harness h;
  const Command c = h.tick();
  EXPECT_EQ(c.linear_mps, 0.0);
  EXPECT_EQ(c.angular_radps, 0.0);
  EXPECT_EQ(c.mode, Mode::kWaiting);
}

TEST(MotionController, GivenIdleTrackerWithAPosition_ThenStandsStill) {
  // Start-up: the tracker has not confirmed five consistent positions yet
  Harness h;
  TrackSample t = following(0.4, 3.0, kT0);
  t.state = TrackState::kIdle;
  const Command c = h.run(t, 40);
  EXPECT_EQ(c.linear_mps, 0.0);
  EXPECT_EQ(c.angular_radps, 0.0);
  EXPECT_EQ(c.mode, Mode::kIdle);
}

TEST(MotionController, GivenBallToTheRight_ThenTurnsClockwise) {
  Harness h;
  const Command c = h.run(following(0.3, 1.0, kT0), 30);
  EXPECT_EQ(c.mode, Mode::kFollowing);
  EXPECT_LT(c.angular_radps, 0.0);
  EXPECT_NEAR(c.angular_radps, -MotionControllerParams{}.bearing_gain_per_s * 0.3, 1e-6);
}

TEST(MotionController, GivenBallToTheLeft_ThenTurnsCounterClockwise) {
  Harness h;
  const Command c = h.run(following(-0.2, 1.0, kT0), 30);
  EXPECT_GT(c.angular_radps, 0.0);
  EXPECT_NEAR(c.angular_radps, MotionControllerParams{}.bearing_gain_per_s * 0.2, 1e-6);
}

TEST(MotionController, GivenBallFartherThanTarget_ThenDrivesForward) {
  Harness h;
  const Command c = h.run(following(0.0, 1.5, kT0), 40);
  EXPECT_NEAR(c.linear_mps, MotionControllerParams{}.distance_gain_per_s * 0.5, 1e-6);
  EXPECT_NEAR(c.angular_radps, 0.0, 1e-12);
}

TEST(MotionController, GivenBallTooClose_ThenBacksOffWithinReverseLimit) {
  Harness h;
  const Command c = h.run(following(0.0, 0.3, kT0), 40);
  EXPECT_LT(c.linear_mps, 0.0);
  EXPECT_NEAR(c.linear_mps, -0.2, 1e-9);  // gain * -0.7 clamped to max_reverse_mps
}

TEST(MotionController, GivenBallAtTargetAndCentred_ThenNoMotion) {
  Harness h;
  const Command c = h.run(following(0.002, 1.01, kT0), 40);  // inside both deadbands
  EXPECT_EQ(c.linear_mps, 0.0);
  EXPECT_EQ(c.angular_radps, 0.0);
}

TEST(MotionController, GivenFarOffCentreBall_ThenTurnsBeforeDriving) {
  Harness h;
  const Command c = h.run(following(0.7, 4.0, kT0), 40);  // beyond slowdown_bearing_rad
  EXPECT_EQ(c.linear_mps, 0.0);
  EXPECT_LT(c.angular_radps, 0.0);
}

TEST(MotionController, GivenLargeErrors_ThenSpeedAccelAndJerkLimited) {
  const MotionControllerParams p = centred();
  Harness h(p);
  double v_prev = 0.0;
  double w_prev = 0.0;
  double av_prev = 0.0;
  double aw_prev = 0.0;
  double max_v = 0.0;
  double max_w = 0.0;
  for (int i = 0; i < 200; ++i) {
    // The ball hops from side to side every second, far away
    const double bearing = (i / 20) % 2 == 0 ? 0.4 : -0.4;
    const Command c = h.tick(following(bearing, 10.0, kT0 + i * kTickNs));
    const double av = (c.linear_mps - v_prev) / 0.05;
    const double aw = (c.angular_radps - w_prev) / 0.05;
    ASSERT_LE(std::abs(av), linear_accel_bound(p, v_prev, c.linear_mps) + 1e-6) << i;
    ASSERT_LE(std::abs(aw), p.max_angular_accel_radps2 + 1e-6) << i;
    ASSERT_LE(std::abs(av - av_prev) / 0.05, p.max_linear_jerk_mps3 + 1e-3) << i;
    ASSERT_LE(std::abs(aw - aw_prev) / 0.05, p.max_angular_jerk_radps3 + 1e-3) << i;
    max_v = std::max(max_v, c.linear_mps);
    max_w = std::max(max_w, std::abs(c.angular_radps));
    v_prev = c.linear_mps;
    w_prev = c.angular_radps;
    av_prev = av;
    aw_prev = aw;
  }
  EXPECT_LE(max_v, p.max_linear_mps + 1e-9);
  EXPECT_GT(max_v, 0.1);  // it did drive
  EXPECT_LE(max_w, p.max_angular_radps + 1e-9);
}

// Ticks from full speed to standing still when a far ball is suddenly at the target distance.
int ticks_to_stop(double brake_mps2) {
  MotionControllerParams p = centred();
  p.max_linear_brake_mps2 = brake_mps2;
  Harness h(p);
  h.run(following(0.0, 3.0, kT0), 60);
  EXPECT_NEAR(h.controller().step(h.now()).linear_mps, p.max_linear_mps, 1e-9);
  int ticks = 0;
  while (ticks < 200 && h.tick(following(0.0, p.target_distance_m, kT0)).linear_mps > 0.0) ++ticks;
  return ticks;
}

TEST(MotionController, GivenBallSuddenlyAtTargetDistance_ThenBrakesHarderThanItAccelerates) {
  // Given full speed (0.8 m/s; acceleration 0.8 m/s^2) toward a ball that is suddenly close:
  // with the brake limit at the acceleration limit, then at 2 m/s^2
  const int same = ticks_to_stop(0.8);
  const int harder = ticks_to_stop(2.0);
  // Then the harder brake stops in fewer control periods (jerk-limited both times)
  EXPECT_GE(same, 20);
  EXPECT_LE(harder, same - 4);
}

TEST(MotionController, GivenSearchingAfterBallLeftRight_ThenRotatesClockwiseInPlace) {
  Harness h;
  const Command c = h.run(with_state(TrackState::kSearching, Side::kRight, kT0), 30);
  EXPECT_EQ(c.mode, Mode::kSearching);
  EXPECT_NEAR(c.angular_radps, -0.8, 1e-9);
  EXPECT_EQ(c.linear_mps, 0.0);
}

TEST(MotionController, GivenSearchingAfterBallLeftLeft_ThenRotatesCounterClockwise) {
  Harness h;
  const Command c = h.run(with_state(TrackState::kSearching, Side::kLeft, kT0), 30);
  EXPECT_NEAR(c.angular_radps, 0.8, 1e-9);
}

TEST(MotionController, GivenSearchingWithUnknownSide_ThenConfiguredDefaultDirection) {
  MotionControllerParams p = centred();
  p.search_left_when_unknown = false;
  Harness h(p);
  const Command c = h.run(with_state(TrackState::kSearching, Side::kUnknown, kT0), 30);
  EXPECT_NEAR(c.angular_radps, -0.8, 1e-9);
}

// A searching sample that still carries the last accepted position (camera frame), lost
// age_ns before this capture.
TrackSample searching_at(double camera_x_m, double camera_z_m, Side tracker_side,
                         std::int64_t stamp_ns, std::int64_t age_ns = 0) {
  TrackSample t = with_state(TrackState::kSearching, tracker_side, stamp_ns);
  t.position_valid = true;
  t.bearing_rad = std::atan2(camera_x_m, camera_z_m);
  t.distance_m = std::hypot(camera_x_m, camera_z_m);
  t.last_accepted_stamp_ns = stamp_ns - age_ns;
  return t;
}

TEST(MotionController, GivenCloseBallRightOfTheCameraButLeftOfTheRobot_ThenSearchesLeft) {
  // Given the shipped rig offsets (left camera 6 cm left of the centreline) and a ball lost
  // 0.5 m ahead, 2 cm right of the camera axis: the tracker calls that side "right"
  Harness h(MotionControllerParams{});
  const Command c = h.run(searching_at(0.02, 0.5, Side::kRight, kT0), 30);
  // Then from the robot's centre the ball is left (4 cm left of the centreline): turn left
  EXPECT_EQ(c.mode, Mode::kSearching);
  EXPECT_NEAR(c.angular_radps, 0.8, 1e-9);
}

TEST(MotionController, GivenBallLostWhileMovingLeftFast_ThenSearchesWhereItWent) {
  // Given a ball last seen 0.1 m right of the robot's centreline at 1 m, moving left at
  // 1 rad/s, lost 0.4 s ago (the robot still): by now it is ~17 degrees to the left
  Harness h(centred());
  TrackSample t = searching_at(0.1, 1.0, Side::kRight, kT0, 400'000'000);
  t.bearing_rate_radps = -1.0;
  const Command c = h.run(t, 30);
  // Then the search turns left, not toward the side of the last fix
  EXPECT_NEAR(c.angular_radps, 0.8, 1e-9);
}

TEST(MotionController,
     GivenBallRollingPastTheRobotsLeftSide_ThenSearchesLeftThoughTheCameraSawItDriftRight) {
  // Given the shipped rig (left camera 6 cm left of the centreline, 10 cm ahead of the centre)
  // and a ball last seen 0.2 m ahead of the camera, 1 cm right of its axis, rolling at 0.9 m/s
  // almost straight back past the robot's left side, lost 0.5 s ago (the robot still). From
  // the camera its bearing grows to the right; a bearing moved on at that rate points right.
  Harness h(MotionControllerParams{});
  TrackSample t = searching_at(0.01, 0.2, Side::kRight, kT0, 500'000'000);
  const PolarRates seen = polar_rates(0.01, 0.2, 0.03, -0.9);
  ASSERT_GT(seen.bearing_radps, 0.3);
  t.bearing_rate_radps = seen.bearing_radps;
  t.distance_rate_mps = seen.range_mps;
  const Command c = h.run(t, 30);
  // Then the search turns left: the ball is now behind the robot on its left
  EXPECT_EQ(c.mode, Mode::kSearching);
  EXPECT_NEAR(c.angular_radps, 0.8, 1e-9);
}

TEST(MotionController, GivenSearchStarted_ThenTheDirectionDoesNotFlipDuringIt) {
  // Given a search that started with the ball on the left
  Harness h(centred());
  h.run(searching_at(-0.3, 1.0, Side::kLeft, kT0), 5);
  // When later searching samples carry a position on the right (same lost ball)
  const Command c = h.run(searching_at(0.3, 1.0, Side::kRight, kT0), 30);
  // Then the robot keeps turning left
  EXPECT_NEAR(c.angular_radps, 0.8, 1e-9);
}

TEST(MotionController, GivenSearchingLongerThanTimeout_ThenGivesUpAndStops) {
  MotionControllerParams p = centred();
  p.search_timeout_ns = 2'000'000'000;
  Harness h(p);
  const TrackSample s = with_state(TrackState::kSearching, Side::kLeft, kT0);
  EXPECT_EQ(h.run(s, 39).mode, Mode::kSearching);  // 1.95 s
  h.run(s, 2);
  const Command c = h.run(s, 30);
  EXPECT_EQ(c.mode, Mode::kSearchGaveUp);
  EXPECT_EQ(c.angular_radps, 0.0);
  EXPECT_EQ(c.linear_mps, 0.0);
  // And a new loss after following searches again from the start
  h.run(following(0.0, 1.0, kT0), 5);
  EXPECT_EQ(h.run(s, 5).mode, Mode::kSearching);
}

TEST(MotionController, GivenTrackStopsArriving_ThenZeroAfterStaleTimeout) {
  Harness h;
  ASSERT_GT(h.run(following(0.0, 2.0, kT0), 40).linear_mps, 0.5);
  // No more samples: 250 ms later still following, after 300 ms exactly zero
  Command c;
  for (int i = 0; i < 5; ++i) c = h.tick();
  EXPECT_EQ(c.mode, Mode::kFollowing);
  c = h.tick();
  c = h.tick();
  EXPECT_EQ(c.mode, Mode::kStale);
  EXPECT_EQ(c.linear_mps, 0.0);
  EXPECT_EQ(c.angular_radps, 0.0);
  // When samples come back, it drives again from zero, smoothly
  c = h.tick(following(0.0, 2.0, kT0));
  EXPECT_EQ(c.mode, Mode::kFollowing);
  EXPECT_LE(c.linear_mps, 0.8 * 0.05 + 1e-9);
}

// input_stale tells the node when to send the stale zero without waiting for its next tick.
TEST(MotionController, GivenTrackAge_ThenInputStaleExactlyAfterTheTimeout) {
  MotionControllerParams p;
  MotionController mc(p);
  EXPECT_FALSE(mc.input_stale(10'000'000'000));  // no track yet: waiting, not stale
  mc.on_track(following(0.0, 2.0, kT0), kT0);
  EXPECT_FALSE(mc.input_stale(kT0 + p.stale_timeout_ns));
  EXPECT_TRUE(mc.input_stale(kT0 + 1 + p.stale_timeout_ns));
  EXPECT_EQ(mc.step(kT0 + 1 + p.stale_timeout_ns).mode, Mode::kStale);
}

TEST(MotionController, GivenEmergencyStop_ThenZeroLatchedUntilCleared) {
  Harness h;
  h.run(following(0.3, 2.0, kT0), 40);
  h.controller().on_estop(true);
  Command c = h.run(following(0.3, 2.0, kT0), 40);  // tracks keep coming
  EXPECT_EQ(c.mode, Mode::kEmergencyStop);
  EXPECT_EQ(c.linear_mps, 0.0);
  EXPECT_EQ(c.angular_radps, 0.0);
  EXPECT_TRUE(h.controller().estop_engaged());
  h.controller().on_estop(false);
  c = h.run(following(0.3, 2.0, kT0), 40);
  EXPECT_EQ(c.mode, Mode::kFollowing);
  EXPECT_GT(c.linear_mps, 0.0);
}

TEST(MotionController, GivenFollowingButPositionTooOld_ThenHoldsStill) {
  Harness h;
  h.run(following(0.3, 2.0, kT0), 40);
  TrackSample t = following(0.3, 2.0, kT0);
  t.capture_stamp_ns = kT0 + 400'000'000;  // last accepted 400 ms before this frame
  const Command c = h.run(t, 40);
  EXPECT_EQ(c.mode, Mode::kHolding);
  EXPECT_EQ(c.linear_mps, 0.0);
  EXPECT_EQ(c.angular_radps, 0.0);
}

TEST(MotionController, GivenCameraLeftOfCentreline_WhenBallOnCameraAxis_ThenTurnsLeftToCentreIt) {
  // Given the shipped rig: left camera 6 cm left of the centreline, 10 cm ahead
  MotionControllerParams p;
  p.bearing_rate_feedforward = 0.0;  // this harness does not move the ball in the image
  p.distance_rate_feedforward = 0.0;
  Harness h(p);
  // When the ball is straight ahead of the left camera, 1 m away
  const Command c = h.run(following(0.0, 1.0, kT0), 40);
  // Then it is left of the robot's centreline: counter-clockwise by gain * atan2(0.06, 1.1)
  EXPECT_GT(c.angular_radps, 0.0);
  EXPECT_NEAR(c.angular_radps, MotionControllerParams{}.bearing_gain_per_s * std::atan2(0.06, 1.1),
              1e-6);
  // And the distance counts from the robot's centre (1.1 m): it drives forward
  EXPECT_GT(c.linear_mps, 0.0);
}

TEST(MotionController, GivenBallMovingRightAndAway_WhenFeedforwardOn_ThenTurnsAndDrivesHarder) {
  // Given a centred ball at the target distance, moving right (0.3 rad/s) and away (0.4 m/s)
  TrackSample t = following(0.0, 1.0, kT0);
  t.bearing_rate_radps = 0.3;
  t.distance_rate_mps = 0.4;
  MotionControllerParams p = centred();
  p.bearing_rate_feedforward = 0.6;
  p.distance_rate_feedforward = 0.6;
  Harness with_ff(p);
  Harness without_ff(centred());
  const Command a = with_ff.run(t, 200);
  const Command b = without_ff.run(t, 200);
  // Then without feedforward a P controller sees no error at all
  EXPECT_EQ(b.angular_radps, 0.0);
  EXPECT_EQ(b.linear_mps, 0.0);
  // And with it the robot turns right and drives on: ff * (rate seen - own motion), settled
  // where w = -0.6 * (0.3 - w) and v = 0.6 * (0.4 + v)
  EXPECT_NEAR(a.angular_radps, -0.6 * 0.3 / 0.4, 1e-3);
  EXPECT_NEAR(a.linear_mps, 0.6 * 0.4 / 0.4, 1e-3);
}

TEST(MotionController, GivenClosedLoopWithSimpleRobot_ThenBallCentredAtTargetDistance) {
  // Given a unicycle robot and a still ball 3 m away, 0.6 rad to the left
  Harness h;
  double rx = 0.0, ry = 0.0, yaw = 0.0;
  const double bx = 3.0 * std::cos(0.6), by = 3.0 * std::sin(0.6);
  double bearing = 0.0, distance = 0.0;
  for (int i = 0; i < 400; ++i) {  // 20 s
    const double dx = bx - rx, dy = by - ry;
    // Camera frame: z forward, x right -> bearing positive to the right
    const double fwd = std::cos(yaw) * dx + std::sin(yaw) * dy;
    const double left = -std::sin(yaw) * dx + std::cos(yaw) * dy;
    bearing = std::atan2(-left, fwd);
    distance = std::hypot(dx, dy);
    const Command c = h.tick(following(bearing, distance, kT0 + i * kTickNs));
    rx += c.linear_mps * std::cos(yaw) * 0.05;
    ry += c.linear_mps * std::sin(yaw) * 0.05;
    yaw += c.angular_radps * 0.05;
  }
  EXPECT_NEAR(distance, 1.0, 0.05);
  EXPECT_NEAR(bearing, 0.0, 0.02);
}

TEST(PolarRates, GivenPointAheadMovingRightAndAway_ThenBearingAndRangeRates) {
  // Given a point 2 m straight ahead moving 0.5 m/s right and 0.3 m/s away
  const PolarRates r = polar_rates(0.0, 2.0, 0.5, 0.3);
  // Then the bearing grows at vx / z and the range at vz
  EXPECT_NEAR(r.bearing_radps, 0.25, 1e-12);
  EXPECT_NEAR(r.range_mps, 0.3, 1e-12);
}

TEST(PolarRates, GivenPointToTheRightMovingForward_ThenBearingShrinks) {
  // Given a point at 45 degrees right (1, 1) moving forward at 1 m/s
  const PolarRates r = polar_rates(1.0, 1.0, 0.0, 1.0);
  // Then the bearing decreases (-x / r^2) and the range grows (z / r)
  EXPECT_NEAR(r.bearing_radps, -0.5, 1e-12);
  EXPECT_NEAR(r.range_mps, 1.0 / std::sqrt(2.0), 1e-12);
}

TEST(PolarRates, GivenPointAtOriginOrNaN_ThenZero) {
  // Given degenerate inputs, Then both rates are zero (no division by zero, no NaN)
  const PolarRates at_origin = polar_rates(0.0, 0.0, 1.0, 1.0);
  EXPECT_EQ(at_origin.bearing_radps, 0.0);
  EXPECT_EQ(at_origin.range_mps, 0.0);
  const PolarRates nan = polar_rates(std::nan(""), 1.0, 1.0, 1.0);
  EXPECT_EQ(nan.bearing_radps, 0.0);
  EXPECT_EQ(nan.range_mps, 0.0);
}

// A unicycle robot, a still ball, a 30 Hz camera whose track velocity is a least-squares fit
// of camera-frame positions over the last 0.5 s (as the tracker does), the controller
// answering each track at once (at least at 20 Hz). Returns the ball's bearing from the robot (rad)
// every 10 ms after start_s.
std::vector<double> bearings_with_fitted_velocity(const MotionControllerParams& p, double ball_x,
                                                  double ball_y, double seconds, double start_s) {
  MotionController c(p);
  double rx = 0.0, ry = 0.0, yaw = 0.0, v = 0.0, w = 0.0;
  struct Seen {
    double t, x, z;
  };
  std::vector<Seen> window;
  std::vector<double> out;
  const int total_ms = static_cast<int>(seconds * 1000);
  for (int ms = 0; ms <= total_ms; ++ms) {
    const std::int64_t now = kT0 + std::int64_t{ms} * 1'000'000;
    const double dx = ball_x - rx, dy = ball_y - ry;
    const double fwd = std::cos(yaw) * dx + std::sin(yaw) * dy;
    const double right = std::sin(yaw) * dx - std::cos(yaw) * dy;
    if ((ms * 3) % 100 < 3) {  // a camera frame every 33 or 34 ms
      const double t = ms * 1e-3;
      window.push_back({t, right, fwd});
      while (window.front().t < t - 0.5) window.erase(window.begin());
      double tm = 0, xm = 0, zm = 0;
      for (const auto& s : window) tm += s.t, xm += s.x, zm += s.z;
      tm /= window.size(), xm /= window.size(), zm /= window.size();
      double stt = 0, stx = 0, stz = 0;
      for (const auto& s : window) {
        stt += (s.t - tm) * (s.t - tm);
        stx += (s.t - tm) * (s.x - xm);
        stz += (s.t - tm) * (s.z - zm);
      }
      const double vx = stt > 0 ? stx / stt : 0.0, vz = stt > 0 ? stz / stt : 0.0;
      TrackSample track = following(std::atan2(right, fwd), std::hypot(right, fwd), now);
      const PolarRates rates = polar_rates(right, fwd, vx, vz);
      track.bearing_rate_radps = rates.bearing_radps;
      track.distance_rate_mps = rates.range_mps;
      // Answered at once, as the node does with each new track.
      const auto response = c.on_track(track, now);
      if (response.command) v = response.command->linear_mps, w = response.command->angular_radps;
    } else if (c.minimum_rate_due(now, 50'000'000, 1'000'000)) {
      const Command cmd = c.step(now);
      v = cmd.linear_mps, w = cmd.angular_radps;
    }
    if (ms * 1e-3 >= start_s && ms % 10 == 0) out.push_back(std::atan2(right, fwd));
    rx += v * std::cos(yaw) * 1e-3;
    ry += v * std::sin(yaw) * 1e-3;
    yaw += w * 1e-3;
  }
  return out;
}

double max_abs(const std::vector<double>& v) {
  double m = 0.0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

TEST(MotionController,
     GivenFittedTrackVelocityAndFeedforward_WhenBallStill_ThenNoGrowingOscillation) {
  // Given the shipped feedforward (0.6) and the track's rates fitted over 0.5 s, a still ball
  // 1.6 m ahead and 7 degrees to the right
  MotionControllerParams p = centred();
  p.bearing_rate_feedforward = 0.6;
  p.distance_rate_feedforward = 0.6;
  p.track_velocity_window_ns = 500'000'000;
  const double a = 7.0 * M_PI / 180;
  // When the loop runs for 12 s
  const auto late =
      bearings_with_fitted_velocity(p, 1.6 * std::cos(a), -1.6 * std::sin(a), 12.0, 6.0);
  // Then the robot has centred the ball and stays centred (no limit cycle), well inside 5 deg
  ASSERT_FALSE(late.empty());
  EXPECT_LT(max_abs(late), 1.0 * M_PI / 180) << "largest bearing in the last 6 s";
}

// Event-driven control and the stamps it answers.

TEST(MotionControllerEvents, GivenNewTracks_ThenEachAnsweredOnceWithItsCaptureStamp) {
  // Given a controller and frames whose stamps need all 64 bits (a double would round them)
  MotionController mc(centred());
  const std::int64_t stamp = 1'733'123'456'789'012'345;
  std::int64_t now = stamp + 4'000'000;
  for (int i = 0; i < 5; ++i, now += 33'000'000) {
    const std::int64_t capture = stamp + i * 33'000'000;
    // When each new track arrives
    const auto r = mc.on_track(following(0.2, 2.0, capture), now);
    // Then it is answered at once by one command carrying exactly its capture stamp
    ASSERT_EQ(r.check, StampCheck::kNew) << i;
    ASSERT_TRUE(r.command.has_value()) << i;
    EXPECT_EQ(r.command->capture_stamp_ns, capture) << i;
    EXPECT_EQ(r.command->mode, Mode::kFollowing) << i;
    // And the same track delivered again is not answered a second time
    const auto again = mc.on_track(following(0.2, 2.0, capture), now + 1'000'000);
    EXPECT_EQ(again.check, StampCheck::kRepeated) << i;
    EXPECT_FALSE(again.command.has_value()) << i;
  }
  // And timer commands answer no track
  EXPECT_EQ(mc.step(now).capture_stamp_ns, 0);
}

TEST(MotionControllerEvents, GivenBadStamps_ThenRejectedAndNothingBuiltOnThem) {
  // Given a controller following a ball straight ahead
  MotionController mc(centred());
  const std::int64_t now = kT0 + 100'000'000;
  ASSERT_TRUE(mc.on_track(following(0.0, 2.0, kT0), now).command);
  const double angular_before = mc.step(now + 1'000'000).angular_radps;
  // When samples with a far-right ball arrive with bad stamps
  const std::int64_t later = now + 10'000'000;
  const struct {
    std::int64_t stamp;
    StampCheck check;
  } bad[] = {{0, StampCheck::kZero},
             {-5, StampCheck::kZero},
             {later + 100'000'001, StampCheck::kFuture},
             {kT0 - 1, StampCheck::kBackwards}};
  for (const auto& b : bad) {
    const auto r = mc.on_track(following(0.5, 2.0, b.stamp), later);
    // Then each is named, none is answered
    EXPECT_EQ(r.check, b.check) << b.stamp;
    EXPECT_FALSE(r.command.has_value()) << b.stamp;
  }
  // And the next command still steers on the last good track (straight on), not the bad ones
  const Command c = mc.step(later + 1'000'000);
  EXPECT_EQ(c.mode, Mode::kFollowing);
  EXPECT_EQ(c.angular_radps, angular_before);
  // And a stamp just inside the tolerance is accepted
  EXPECT_EQ(mc.on_track(following(0.0, 2.0, later + 100'000'000), later).check, StampCheck::kNew);
}

TEST(MotionControllerEvents, GivenInputWentStale_ThenAnEarlierStreamMayStartAgain) {
  // Given a track, then silence beyond the stale timeout (the source restarted)
  MotionController mc(centred());
  ASSERT_TRUE(mc.on_track(following(0.0, 2.0, kT0), kT0).command);
  const std::int64_t later = kT0 + 400'000'000;
  ASSERT_EQ(mc.step(later).mode, Mode::kStale);
  // When the new stream's stamps lie before the old ones (a clock set back)
  const auto r = mc.on_track(following(0.0, 2.0, kT0 - 1'000'000'000), later);
  // Then it is accepted: the old stream is over, it cannot steer any more
  EXPECT_EQ(r.check, StampCheck::kNew);
  ASSERT_TRUE(r.command.has_value());
  EXPECT_EQ(r.command->mode, Mode::kFollowing);
}

TEST(MotionControllerEvents, GivenNoTracks_ThenTheTimerKeepsTheMinimumRate) {
  // Given a controller checked every 5 ms for a 20 Hz minimum rate, without any track
  MotionController mc(centred());
  constexpr std::int64_t kPeriod = 50'000'000, kCheck = 5'000'000;
  std::vector<std::int64_t> issued;
  // When the timer runs for 2 s
  for (std::int64_t now = kT0; now < kT0 + 2'000'000'000; now += kCheck) {
    if (mc.minimum_rate_due(now, kPeriod, kCheck)) {
      mc.step(now);
      issued.push_back(now);
    }
  }
  // Then no two commands are further apart than the period, and there are about 20 per second
  ASSERT_GE(issued.size(), 40u);
  for (size_t i = 1; i < issued.size(); ++i) EXPECT_LE(issued[i] - issued[i - 1], kPeriod) << i;
  EXPECT_LE(issued.size(), 45u);
}

TEST(MotionControllerEvents, GivenTracksFasterThanTheMinimumRate_ThenTheTimerAddsNothing) {
  // Given a track every 35 ms and a 20 Hz minimum rate checked every 5 ms
  MotionController mc(centred());
  constexpr std::int64_t kPeriod = 50'000'000, kCheck = 5'000'000;
  int timer_commands = 0, track_commands = 0;
  for (std::int64_t ms = 0; ms < 2000; ms += 5) {
    const std::int64_t now = kT0 + ms * 1'000'000;
    if (ms % 35 == 0) track_commands += mc.on_track(following(0.1, 2.0, now), now).command ? 1 : 0;
    if (mc.minimum_rate_due(now, kPeriod, kCheck)) {
      mc.step(now);
      ++timer_commands;
    }
  }
  // Then every command answers a track: the timer never finds a 45 ms gap
  EXPECT_EQ(track_commands, 58);
  EXPECT_EQ(timer_commands, 0);
}

TEST(MotionControllerEvents, GivenTracksAtIrregularTimes_ThenAccelerationLimitsHold) {
  // Given the shipped limits and tracks arriving 10 to 45 ms apart, the ball hopping sides
  const MotionControllerParams p;
  MotionController mc(p);
  std::int64_t now = kT0;
  double v_prev = 0.0, w_prev = 0.0;
  for (int i = 0; i < 300; ++i) {
    const std::int64_t dt_ns = 10'000'000 + (i * 7919 % 36) * 1'000'000;
    now += dt_ns;
    const double bearing = (i / 25) % 2 == 0 ? 0.4 : -0.4;
    const auto r = mc.on_track(following(bearing, 6.0, now), now);
    ASSERT_TRUE(r.command.has_value());
    // Then the velocity never changes faster than the acceleration limits over the real step
    const double dt_s = static_cast<double>(dt_ns) * 1e-9;
    EXPECT_LE(std::abs(r.command->linear_mps - v_prev) / dt_s,
              linear_accel_bound(p, v_prev, r.command->linear_mps) + 1e-6)
        << i;
    EXPECT_LE(std::abs(r.command->angular_radps - w_prev) / dt_s, p.max_angular_accel_radps2 + 1e-6)
        << i;
    v_prev = r.command->linear_mps;
    w_prev = r.command->angular_radps;
  }
}

TEST(MotionControllerNames, GivenModes_ThenStableNames) {
  EXPECT_EQ(to_string(Mode::kSearchGaveUp), "search_gave_up");
  EXPECT_EQ(to_string(Mode::kEmergencyStop), "emergency_stop");
}

}  // namespace
}  // namespace stereoball::motion_controller
