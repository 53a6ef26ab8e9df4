#pragma once
// Inputs and outputs of the motion controller core. They mirror the parts of
// idl/stereoball.idl BallTrack / VelocityCommand the controller uses.

#include <cstdint>
#include <string_view>

#include "tracker/core/track_state.hpp"

namespace stereoball::motion_controller {

/// Tracker state as reported on ball/track (the tracker's own declaration).
using TrackState = tracker::TrackState;

/// Side where the ball was last seen (the tracker's own declaration).
using Side = tracker::Side;

/// The part of one ball/track sample the controller needs.
struct TrackSample {
  TrackState state = TrackState::kIdle;
  bool position_valid = false;      ///< bearing/distance hold an accepted estimate
  double bearing_rad = 0.0;         ///< atan2(x, z); positive = ball to the RIGHT
  double distance_m = 0.0;          ///< horizontal distance to the ball, metres
  double bearing_rate_radps = 0.0;  ///< d(bearing)/dt seen by the camera, rad/s
  double distance_rate_mps = 0.0;   ///< d(distance)/dt seen by the camera, m/s
  Side last_seen_side = Side::kUnknown;
  std::int64_t capture_stamp_ns = 0;        ///< capture stamp of the frame behind this sample
  std::int64_t last_accepted_stamp_ns = 0;  ///< capture stamp of the last accepted detection
};

/// What the controller is doing (for logs and health).
enum class Mode {
  kWaiting,       ///< no track received yet
  kIdle,          ///< tracker idle: stand still
  kFollowing,     ///< centring the ball at the target distance
  kHolding,       ///< following, but the position is too old to steer on: slow to a stop
  kSearching,     ///< rotating in place toward the last-seen side
  kSearchGaveUp,  ///< searched for search_timeout_ns without success: stopped
  kStale,         ///< no track for stale_timeout_ns: zero
  kEmergencyStop  ///< emergency stop latched: zero
};

/// Velocity command for a differential-drive base.
struct Command {
  double linear_mps = 0.0;     ///< forward speed, m/s
  double angular_radps = 0.0;  ///< yaw rate, rad/s, positive = counter-clockwise (turn left)
  Mode mode = Mode::kWaiting;
  /// Capture stamp of the ball/track sample this command answered, ns since epoch; 0 for a
  /// command of the minimum-rate timer, a stale-input stop or an emergency stop.
  std::int64_t capture_stamp_ns = 0;
};

/// Verdict on the capture stamp of an arriving track sample.
enum class StampCheck {
  kNew,        ///< later than every stamp before it: stored and answered with a command
  kRepeated,   ///< the same stamp as the last stored sample: no new frame, nothing to answer
  kZero,       ///< zero or negative: the source never set it
  kFuture,     ///< later than the receiver's clock plus future_stamp_tolerance_ns
  kBackwards,  ///< earlier than the last stored sample's stamp while that stream is live
};

/// Rates of change, as seen by the camera, of a point's bearing and horizontal range.
struct PolarRates {
  double bearing_radps = 0.0;  ///< d(atan2(x, z))/dt, rad/s (positive = moving right)
  double range_mps = 0.0;      ///< d(sqrt(x^2 + z^2))/dt, m/s (positive = moving away)
};

/// Bearing and range rates of a point at (x_m, z_m) moving at (vx_mps, vz_mps) in the camera's
/// x (right) / z (forward) plane; zero when the point is at the origin or a value is not finite.
PolarRates polar_rates(double x_m, double z_m, double vx_mps, double vz_mps);

/// Lower-case name of a mode, e.g. "searching".
std::string_view to_string(Mode m);
/// What a stamp verdict means, e.g. "zero (never set)".
std::string_view to_string(StampCheck c);

}  // namespace stereoball::motion_controller
