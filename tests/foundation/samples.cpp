#include "samples.hpp"

#include <random>

namespace stereoball::testing {
namespace {

double value(std::mt19937& rng) {
  return std::uniform_real_distribution<double>(-100, 100)(rng);
}

template <size_t N>
void fill_array(double (&a)[N], std::mt19937& rng) {
  for (auto& v : a) v = value(rng);
}

dds_sequence_double doubles(SampleStorage& s, std::mt19937& rng, size_t n) {
  auto& v = s.doubles.emplace_back(n);
  for (auto& d : v) d = value(rng);
  return {static_cast<uint32_t>(n), static_cast<uint32_t>(n), v.data(), false};
}

stereoball_msg_EyeImage eye(SampleStorage& s, std::mt19937& rng, uint32_t w, uint32_t h) {
  auto& bytes = s.bytes.emplace_back(static_cast<size_t>(w) * h * 3);
  for (auto& b : bytes) b = static_cast<uint8_t>(rng());
  stereoball_msg_EyeImage e{};
  e.capture_stamp_ns = static_cast<int64_t>(rng()) * 1000 + 17;
  e.width_px = w;
  e.height_px = h;
  e.step_bytes = w * 3;
  e.data = {static_cast<uint32_t>(bytes.size()), static_cast<uint32_t>(bytes.size()), bytes.data(),
            false};
  return e;
}

stereoball_msg_EyeCircle circle(std::mt19937& rng) {
  return {static_cast<float>(value(rng)), static_cast<float>(value(rng)),
          static_cast<float>(value(rng)), static_cast<float>(value(rng))};
}

}  // namespace

void fill(stereoball_msg_StereoFrame& m, SampleStorage& s, uint32_t seed, uint32_t width,
          uint32_t height) {
  std::mt19937 rng(seed);
  m.seq = seed + 1000;
  m.stamp_ns = 1'700'000'000'000'000'000 + seed;
  m.source = s.str("test-source-" + std::to_string(seed));
  m.encoding = s.str("bgr8");
  m.rectified = (seed % 2) == 1;
  m.left = eye(s, rng, width, height);
  m.right = eye(s, rng, width, height);
}

void fill(stereoball_msg_StereoCalibration& m, SampleStorage& s, uint32_t seed) {
  std::mt19937 rng(seed);
  m.stamp_ns = 1'700'000'000'000'000'000 + seed;
  m.width_px = 640 + seed;
  m.height_px = 480 + seed;
  fill_array(m.k1, rng);
  m.d1 = doubles(s, rng, 5);
  fill_array(m.k2, rng);
  m.d2 = doubles(s, rng, 8);
  fill_array(m.r, rng);
  fill_array(m.t, rng);
  fill_array(m.r1, rng);
  fill_array(m.r2, rng);
  fill_array(m.p1, rng);
  fill_array(m.p2, rng);
  fill_array(m.q, rng);
  m.rms_px = value(rng);
  m.source = s.str("calibration-" + std::to_string(seed));
}

void fill(stereoball_msg_BallDetection& m, SampleStorage& s, uint32_t seed) {
  std::mt19937 rng(seed);
  m.frame_seq = seed + 7;
  m.capture_stamp_ns = 1'700'000'000'000'000'000 + seed;
  m.publish_stamp_ns = m.capture_stamp_ns + 12345;
  m.status = static_cast<stereoball_msg_DetectionStatus>(1 + seed % 5);
  m.reason = s.str("reason " + std::to_string(seed));
  m.left = circle(rng);
  m.right = circle(rng);
  m.row_residual_px = static_cast<float>(value(rng));
  fill_array(m.position_m, rng);
  m.depth_from_size_m = static_cast<float>(value(rng));
  m.candidates_left = seed + 3;
  m.candidates_right = seed + 4;
  m.processing_ms = static_cast<float>(value(rng));
  m.patch_valid = true;
  for (auto& b : m.patch_rgb) b = static_cast<uint8_t>(rng());
}

void fill(stereoball_msg_BallTrack& m, SampleStorage& s, uint32_t seed) {
  std::mt19937 rng(seed);
  m.frame_seq = seed + 9;
  m.capture_stamp_ns = 1'700'000'000'000'000'000 + seed;
  m.publish_stamp_ns = m.capture_stamp_ns + 999;
  m.state = static_cast<stereoball_msg_TrackState>(1 + seed % 2);
  m.verdict = static_cast<stereoball_msg_TrackVerdict>(1 + seed % 6);
  m.reason = s.str("track reason " + std::to_string(seed));
  m.position_valid = true;
  fill_array(m.position_m, rng);
  fill_array(m.velocity_mps, rng);
  m.bearing_rad = value(rng);
  m.distance_m = value(rng);
  m.last_seen_side = static_cast<stereoball_msg_Side>(1 + seed % 2);
  m.ssd = value(rng);
  m.last_accepted_stamp_ns = m.capture_stamp_ns - 5;
}

void fill(stereoball_msg_VelocityCommand& m, SampleStorage& s, uint32_t seed) {
  std::mt19937 rng(seed);
  m.seq = seed + 11;
  m.stamp_ns = 1'700'000'000'000'000'000 + seed;
  m.linear_mps = value(rng);
  m.angular_radps = value(rng);
  m.source = s.str("controller-" + std::to_string(seed));
}

void fill(stereoball_msg_EmergencyStop& m, SampleStorage& s, uint32_t seed) {
  m.stamp_ns = 1'700'000'000'000'000'000 + seed;
  m.engaged = true;
  m.reason = s.str("operator pressed stop " + std::to_string(seed));
}

void fill(stereoball_msg_GroundTruth& m, SampleStorage& s, uint32_t seed) {
  std::mt19937 rng(seed);
  m.frame_seq = seed + 13;
  m.stamp_ns = 1'700'000'000'000'000'000 + seed;
  m.sim_time_s = value(rng);
  m.scenario = s.str("scenario-" + std::to_string(seed));
  m.ball_present = true;
  m.ball_radius_m = value(rng);
  fill_array(m.ball_world_m, rng);
  fill_array(m.ball_camera_m, rng);
  m.ball_visible_left = true;
  m.ball_visible_right = seed % 2 == 0;
  fill_array(m.ball_left_px, rng);
  fill_array(m.ball_right_px, rng);
  m.robot_x_m = value(rng);
  m.robot_y_m = value(rng);
  m.robot_yaw_rad = value(rng);
  m.robot_linear_mps = value(rng);
  m.robot_angular_radps = value(rng);
}

void fill(stereoball_msg_ComponentStatus& m, SampleStorage& s, uint32_t seed) {
  std::mt19937 rng(seed);
  m.component = s.str("component-" + std::to_string(seed));
  m.host = s.str("host-" + std::to_string(seed));
  m.pid = static_cast<int32_t>(seed + 100);
  m.stamp_ns = 1'700'000'000'000'000'000 + seed;
  m.uptime_s = value(rng);
  m.healthy = seed % 2 == 0;
  m.state = s.str("state-" + std::to_string(seed));
  auto& rates = s.rates.emplace_back();
  for (uint32_t i = 0; i < 3; ++i) {
    rates.push_back(
        {s.str("topic/" + std::to_string(i)), static_cast<float>(value(rng)), rng(), rng()});
  }
  m.rates = {3, 3, rates.data(), false};
  auto& counters = s.counters.emplace_back();
  for (uint32_t i = 0; i < 2; ++i)
    counters.push_back({s.str("counter" + std::to_string(i)), rng()});
  m.counters = {2, 2, counters.data(), false};
  m.errors = seed + 5;
  m.last_error = s.str("last error " + std::to_string(seed));
}

}  // namespace stereoball::testing
