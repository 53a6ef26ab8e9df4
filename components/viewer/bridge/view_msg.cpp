#include "viewer/bridge/view_msg.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>

#include "common/msg/msg_names.hpp"

namespace stereoball::viewer {
namespace {

std::string text(const char* s) {
  return s ? s : "";
}

Circle circle(const stereoball_msg_EyeCircle& c) {
  return {c.x_px, c.y_px, c.radius_px, c.score};
}

Vec3 vec(const double (&v)[3]) {
  return {v[0], v[1], v[2]};
}

double latency_ms(int64_t publish_ns, int64_t capture_ns) {
  return publish_ns > 0 && capture_ns > 0 ? (publish_ns - capture_ns) / 1e6 : 0.0;
}

// An enum field read as its integer, without an enum-typed load: a value outside the
// enumerators (which Cyclone's deserializer refuses, but a sample built in this process may
// hold) must print as unknown, not be undefined behaviour.
template <typename Enum>
std::int32_t raw(const Enum& e) {
  static_assert(sizeof(Enum) == sizeof(std::int32_t), "IDL enums are 32-bit");
  std::int32_t v;
  std::memcpy(&v, &e, sizeof v);
  return v;
}

std::string status_name(std::int32_t s) {
  return msg::lower_or_number(msg::detection_status_name(s), s);
}

std::string state_name(std::int32_t s) {
  return msg::lower_or_number(msg::track_state_name(s), s);
}

std::string verdict_name(std::int32_t v) {
  return msg::lower_or_number(msg::track_verdict_name(v), v);
}

// A side outside the enum reads as "unknown" (the viewer has no search side then).
std::string side_name(std::int32_t s) {
  return msg::side_name(s) ? msg::lower_or_number(msg::side_name(s), s) : "unknown";
}

}  // namespace

Detection to_view(const stereoball_msg_BallDetection& m) {
  Detection d;
  d.frame_seq = m.frame_seq;
  d.capture_stamp_ns = m.capture_stamp_ns;
  d.found = raw(m.status) == stereoball_msg_DETECTION_FOUND;
  d.status = status_name(raw(m.status));
  d.reason = text(m.reason);
  d.left = circle(m.left);
  d.right = circle(m.right);
  d.row_residual_px = m.row_residual_px;
  d.position_m = vec(m.position_m);
  d.candidates_left = m.candidates_left;
  d.candidates_right = m.candidates_right;
  d.processing_ms = m.processing_ms;
  d.latency_ms = latency_ms(m.publish_stamp_ns, m.capture_stamp_ns);
  return d;
}

Track to_view(const stereoball_msg_BallTrack& m) {
  Track t;
  t.frame_seq = m.frame_seq;
  t.capture_stamp_ns = m.capture_stamp_ns;
  t.state = state_name(raw(m.state));
  t.verdict = verdict_name(raw(m.verdict));
  t.reason = text(m.reason);
  const std::int32_t verdict = raw(m.verdict);
  t.accepted = verdict == stereoball_msg_VERDICT_STARTUP_ACCEPTED ||
               verdict == stereoball_msg_VERDICT_BLOCK_MATCH_ACCEPTED ||
               verdict == stereoball_msg_VERDICT_STATISTICS_ACCEPTED;
  t.position_valid = m.position_valid;
  t.position_m = vec(m.position_m);
  t.velocity_mps = vec(m.velocity_mps);
  t.bearing_rad = m.bearing_rad;
  t.distance_m = m.distance_m;
  t.last_seen_side = side_name(raw(m.last_seen_side));
  t.ssd = m.ssd;
  t.latency_ms = latency_ms(m.publish_stamp_ns, m.capture_stamp_ns);
  return t;
}

Command to_view(const stereoball_msg_VelocityCommand& m) {
  return {m.stamp_ns, m.linear_mps, m.angular_radps};
}

Estop to_view(const stereoball_msg_EmergencyStop& m) {
  return {m.stamp_ns, m.engaged, text(m.reason)};
}

Truth to_view(const stereoball_msg_GroundTruth& m) {
  Truth t;
  t.frame_seq = m.frame_seq;
  t.stamp_ns = m.stamp_ns;
  t.ball_present = m.ball_present;
  t.ball_radius_m = m.ball_radius_m;
  t.ball_world_m = vec(m.ball_world_m);
  t.ball_camera_m = vec(m.ball_camera_m);
  t.robot_x_m = m.robot_x_m;
  t.robot_y_m = m.robot_y_m;
  t.robot_yaw_rad = m.robot_yaw_rad;
  return t;
}

Health to_view(const stereoball_msg_ComponentStatus& m) {
  Health h;
  h.component = text(m.component);
  h.host = text(m.host);
  h.pid = m.pid;
  h.stamp_ns = m.stamp_ns;
  h.healthy = m.healthy;
  h.state = text(m.state);
  // Bounded: a heartbeat lists a node's topics, never thousands of them.
  const uint32_t n = std::min<uint32_t>(m.rates._length, 64);
  for (uint32_t i = 0; i < n && m.rates._buffer; ++i) {
    const auto& r = m.rates._buffer[i];
    h.rates.push_back({text(r.topic), r.rate_hz, r.count, r.dropped});
  }
  h.errors = m.errors;
  h.last_error = text(m.last_error);
  return h;
}

}  // namespace stereoball::viewer
