// libFuzzer target: the conversion of every incoming DDS sample type into core types, as the
// readers do it (stereo/frame has its own target, fuzz_frame_decode). Fields get any value
// the wire can carry: Cyclone's deserializer range-checks enums and booleans and terminates
// strings, so those are drawn within range; numbers take any bit pattern (NaN, inf, huge).

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "ball_detector/node/detection_msg.hpp"
#include "fuzz_input.hpp"
#include "motion_controller/node/command_msg.hpp"
#include "simulator/node/ground_truth_msg.hpp"
#include "stereo/core/rectifier.hpp"
#include "stereo/msg/calibration_msg.hpp"
#include "tracker/core/tracker.hpp"
#include "tracker/node/track_msg.hpp"

namespace {

using stereoball::fuzz::FuzzInput;

void calibration(FuzzInput& in) {
  stereoball_msg_StereoCalibration msg{};
  msg.width_px = in.take<uint32_t>();
  msg.height_px = in.take<uint32_t>();
  in.fill(msg.k1);
  in.fill(msg.k2);
  in.fill(msg.r);
  in.fill(msg.t);
  in.fill(msg.r1);
  in.fill(msg.r2);
  in.fill(msg.p1);
  in.fill(msg.p2);
  in.fill(msg.q);
  msg.rms_px = in.take<double>();
  std::vector<double> d1(in.choice(16)), d2(in.choice(16));
  for (auto& v : d1) v = in.take<double>();
  for (auto& v : d2) v = in.take<double>();
  msg.d1._buffer = d1.data();
  msg.d1._length = msg.d1._maximum = static_cast<uint32_t>(d1.size());
  msg.d2._buffer = d2.data();
  msg.d2._length = msg.d2._maximum = static_cast<uint32_t>(d2.size());
  std::string source = in.text(64);
  msg.source = source.data();
  // The ball_detector's limit; rectification tables only for small images (speed).
  auto calib = stereoball::stereo::calibration_from_message(msg, {1920, 1080});
  if (calib && calib->image_size.area() <= 160 * 120)
    (void)stereoball::stereo::Rectifier::create(*calib);
}

void fill_circle(FuzzInput& in, stereoball_msg_EyeCircle& c) {
  c.x_px = in.take<float>();
  c.y_px = in.take<float>();
  c.radius_px = in.take<float>();
  c.score = in.take<float>();
}

void detection(FuzzInput& in) {
  namespace tr = stereoball::tracker;
  tr::Tracker tracker{tr::TrackerParams{}};
  int64_t now_ns = 0;
  std::string reason;
  // Several detections in a row drive the tracker through its states.
  while (in.left() > 0) {
    stereoball_msg_BallDetection msg{};
    msg.frame_seq = in.take<uint64_t>();
    msg.capture_stamp_ns = in.take<int64_t>();
    msg.status = static_cast<stereoball_msg_DetectionStatus>(in.choice(7));
    reason = in.text(32);
    msg.reason = reason.data();
    fill_circle(in, msg.left);
    fill_circle(in, msg.right);
    msg.row_residual_px = in.take<float>();
    in.fill(msg.position_m);
    msg.depth_from_size_m = in.take<float>();
    msg.patch_valid = in.flag();
    const uint8_t shade = in.take<uint8_t>();
    for (auto& p : msg.patch_rgb) p = shade;
    const auto converted = tr::to_detection(msg, in.take<uint16_t>());
    now_ns += 1 + in.take<uint32_t>();
    (void)tracker.step(converted.detection, now_ns);
  }
}

void track(FuzzInput& in) {
  stereoball_msg_BallTrack msg{};
  msg.frame_seq = in.take<uint64_t>();
  msg.capture_stamp_ns = in.take<int64_t>();
  msg.publish_stamp_ns = in.take<int64_t>();
  msg.state = static_cast<stereoball_msg_TrackState>(in.choice(3));
  msg.verdict = static_cast<stereoball_msg_TrackVerdict>(in.choice(7));
  std::string reason = in.text(32);
  msg.reason = reason.data();
  msg.position_valid = in.flag();
  in.fill(msg.position_m);
  in.fill(msg.velocity_mps);
  msg.bearing_rad = in.take<double>();
  msg.distance_m = in.take<double>();
  msg.last_seen_side = static_cast<stereoball_msg_Side>(in.choice(3));
  msg.ssd = in.take<double>();
  msg.last_accepted_stamp_ns = in.take<int64_t>();
  (void)stereoball::ball_detector::from_message(msg);
  (void)stereoball::motion_controller::to_sample(msg);
}

void velocity(FuzzInput& in) {
  stereoball_msg_VelocityCommand msg{};
  msg.seq = in.take<uint64_t>();
  msg.stamp_ns = in.take<int64_t>();
  msg.linear_mps = in.take<double>();
  msg.angular_radps = in.take<double>();
  std::string source = in.text(32);
  msg.source = source.data();
  (void)stereoball::simulator::command_from_msg(msg, in.take<int64_t>(), in.take<int64_t>(),
                                                in.take<double>());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  FuzzInput in(data, size);
  switch (in.choice(4)) {
    case 0:
      calibration(in);
      break;
    case 1:
      detection(in);
      break;
    case 2:
      track(in);
      break;
    default:
      velocity(in);
      break;
  }
  return 0;
}
