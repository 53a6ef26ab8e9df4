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

// A controller ticking at 20 Hz; every tick may deliver a fresh track first.
class Harness {
 public:
  explicit Harness(const MotionControllerParams& p = centred()) : c_(p) {}
  Command tick() {
    now_ += kTickNs;
    return c_.step(now_);
  }
  Command tick(const TrackSample& t) {
    now_ += kTickNs;
    c_.on_track(t, now_);
    return c_.step(now_);
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
    ASSERT_LE(std::abs(av), p.max_linear_accel_mps2 + 1e-6) << i;
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
  mc.on_track(following(0.0, 2.0, kT0), 1'000'000'000);
  EXPECT_FALSE(mc.input_stale(1'000'000'000 + p.stale_timeout_ns));
  EXPECT_TRUE(mc.input_stale(1'000'000'001 + p.stale_timeout_ns));
  EXPECT_EQ(mc.step(1'000'000'001 + p.stale_timeout_ns).mode, Mode::kStale);
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
// of camera-frame positions over the last 0.5 s (as the tracker does), the controller at
// 20 Hz. Returns the ball's bearing from the robot (rad) every 10 ms after start_s.
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
      c.on_track(track, now);
    }
    if (ms % 50 == 0) {
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

TEST(MotionControllerNames, GivenModes_ThenStableNames) {
  EXPECT_EQ(to_string(Mode::kSearchGaveUp), "search_gave_up");
  EXPECT_EQ(to_string(Mode::kEmergencyStop), "emergency_stop");
}

}  // namespace
}  // namespace stereoball::motion_controller
