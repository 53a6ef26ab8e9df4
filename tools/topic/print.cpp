#include "print.hpp"

#include <cstdio>
#include <sstream>

#include "common/msg/msg_names.hpp"

namespace stereoball::tools {
namespace {

const char* str(const char* s) {
  return s ? s : "";
}

std::string fmt(const char* format, double value) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, value);
  return buf;
}

template <size_t N>
std::string vec(const double (&v)[N], const char* format = "%.4f") {
  std::string out = "[";
  for (size_t i = 0; i < N; ++i) out += (i ? ", " : "") + fmt(format, v[i]);
  return out + "]";
}

std::string seq(const dds_sequence_double& s) {
  std::string out = "[";
  for (uint32_t i = 0; i < s._length; ++i) out += (i ? ", " : "") + fmt("%.6g", s._buffer[i]);
  return out + "]";
}

std::string eye(const stereoball_msg_EyeImage& e) {
  std::ostringstream os;
  os << e.width_px << "x" << e.height_px << " step " << e.step_bytes << " bytes " << e.data._length
     << " capture_stamp_ns " << e.capture_stamp_ns;
  return os.str();
}

std::string circle(const stereoball_msg_EyeCircle& c) {
  return "{x_px: " + fmt("%.2f", c.x_px) + ", y_px: " + fmt("%.2f", c.y_px) +
         ", radius_px: " + fmt("%.2f", c.radius_px) + ", score: " + fmt("%.3f", c.score) + "}";
}

std::string_view status_name(stereoball_msg_DetectionStatus s) {
  return msg::detection_status_name(s).value_or("?");
}

std::string_view state_name(stereoball_msg_TrackState s) {
  return msg::track_state_name(s).value_or("?");
}

std::string_view side_name(stereoball_msg_Side s) {
  return msg::side_name(s).value_or("?");
}

std::string_view verdict_name(stereoball_msg_TrackVerdict v) {
  return msg::track_verdict_name(v).value_or("?");
}

}  // namespace

std::string to_text(const stereoball_msg_StereoFrame& m) {
  std::ostringstream os;
  os << "seq: " << m.seq << "\nstamp_ns: " << m.stamp_ns << "\nsource: " << str(m.source)
     << "\nencoding: " << str(m.encoding) << "\nrectified: " << (m.rectified ? "true" : "false")
     << "\nleft: " << eye(m.left) << "\nright: " << eye(m.right) << "\n";
  return os.str();
}

std::string to_text(const stereoball_msg_StereoCalibration& m) {
  std::ostringstream os;
  os << "stamp_ns: " << m.stamp_ns << "\nsize_px: " << m.width_px << "x" << m.height_px
     << "\nk1: " << vec(m.k1) << "\nd1: " << seq(m.d1) << "\nk2: " << vec(m.k2)
     << "\nd2: " << seq(m.d2) << "\nr: " << vec(m.r) << "\nt_m: " << vec(m.t, "%.5f")
     << "\np1: " << vec(m.p1) << "\np2: " << vec(m.p2) << "\nrms_px: " << m.rms_px
     << "\nsource: " << str(m.source) << "\n";
  return os.str();
}

std::string to_text(const stereoball_msg_BallDetection& m) {
  std::ostringstream os;
  os << "frame_seq: " << m.frame_seq << "\ncapture_stamp_ns: " << m.capture_stamp_ns
     << "\nstatus: " << status_name(m.status) << "\nreason: " << str(m.reason)
     << "\nleft: " << circle(m.left) << "\nright: " << circle(m.right)
     << "\nrow_residual_px: " << fmt("%.2f", m.row_residual_px)
     << "\nposition_m: " << vec(m.position_m)
     << "\ndepth_from_size_m: " << fmt("%.3f", m.depth_from_size_m)
     << "\ncandidates: " << m.candidates_left << " left, " << m.candidates_right << " right"
     << "\nprocessing_ms: " << fmt("%.2f", m.processing_ms)
     << "\npatch: " << (m.patch_valid ? "21x21 rgb" : "none") << "\n";
  return os.str();
}

std::string to_text(const stereoball_msg_BallTrack& m) {
  std::ostringstream os;
  os << "frame_seq: " << m.frame_seq << "\nstate: " << state_name(m.state)
     << "\nverdict: " << verdict_name(m.verdict) << "\nreason: " << str(m.reason)
     << "\nposition_valid: " << (m.position_valid ? "true" : "false")
     << "\nposition_m: " << vec(m.position_m) << "\nvelocity_mps: " << vec(m.velocity_mps)
     << "\nbearing_rad: " << fmt("%.4f", m.bearing_rad)
     << "\ndistance_m: " << fmt("%.3f", m.distance_m)
     << "\nlast_seen_side: " << side_name(m.last_seen_side) << "\nssd: " << fmt("%.0f", m.ssd)
     << "\n";
  return os.str();
}

std::string to_text(const stereoball_msg_VelocityCommand& m) {
  std::ostringstream os;
  os << "seq: " << m.seq << "\nstamp_ns: " << m.stamp_ns
     << "\nlinear_mps: " << fmt("%.3f", m.linear_mps)
     << "\nangular_radps: " << fmt("%.3f", m.angular_radps) << "\nsource: " << str(m.source)
     << "\n";
  return os.str();
}

std::string to_text(const stereoball_msg_EmergencyStop& m) {
  std::ostringstream os;
  os << "stamp_ns: " << m.stamp_ns << "\nengaged: " << (m.engaged ? "true" : "false")
     << "\nreason: " << str(m.reason) << "\n";
  return os.str();
}

std::string to_text(const stereoball_msg_GroundTruth& m) {
  std::ostringstream os;
  os << "frame_seq: " << m.frame_seq << "\nsim_time_s: " << fmt("%.3f", m.sim_time_s)
     << "\nscenario: " << str(m.scenario)
     << "\nball_present: " << (m.ball_present ? "true" : "false")
     << "\nball_world_m: " << vec(m.ball_world_m) << "\nball_camera_m: " << vec(m.ball_camera_m)
     << "\nball_visible: left " << (m.ball_visible_left ? "yes" : "no") << ", right "
     << (m.ball_visible_right ? "yes" : "no") << "\nball_left_px: " << vec(m.ball_left_px, "%.2f")
     << "\nball_right_px: " << vec(m.ball_right_px, "%.2f") << "\nrobot: x_m "
     << fmt("%.3f", m.robot_x_m) << " y_m " << fmt("%.3f", m.robot_y_m) << " yaw_rad "
     << fmt("%.3f", m.robot_yaw_rad) << "\n";
  return os.str();
}

std::string to_text(const stereoball_msg_ComponentStatus& m) {
  std::ostringstream os;
  os << "component: " << str(m.component) << " (pid " << m.pid << " on " << str(m.host) << ")"
     << "\nuptime_s: " << fmt("%.1f", m.uptime_s) << "\nhealthy: " << (m.healthy ? "true" : "false")
     << "\nstate: " << str(m.state) << "\nerrors: " << m.errors
     << "\nlast_error: " << str(m.last_error) << "\nrates:\n";
  for (uint32_t i = 0; i < m.rates._length; ++i) {
    const auto& r = m.rates._buffer[i];
    os << "  " << str(r.topic) << ": " << fmt("%.1f", r.rate_hz) << " Hz, count " << r.count
       << ", dropped " << r.dropped << "\n";
  }
  if (m.counters._length) os << "counters:\n";
  for (uint32_t i = 0; i < m.counters._length; ++i) {
    os << "  " << str(m.counters._buffer[i].name) << ": " << m.counters._buffer[i].value << "\n";
  }
  return os.str();
}

}  // namespace stereoball::tools
