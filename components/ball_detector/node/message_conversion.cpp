#include "ball_detector/node/message_conversion.hpp"

#include <algorithm>
#include <cmath>

namespace stereoball::ball_detector {
namespace {

template <int R, int C>
void copy_out(const cv::Matx<double, R, C>& m, double* out) {
  std::copy(m.val, m.val + R * C, out);
}

dds_sequence_double sequence_of(const std::vector<double>& v) {
  dds_sequence_double s{};
  s._length = s._maximum = static_cast<std::uint32_t>(v.size());
  s._buffer = const_cast<double*>(v.data());
  s._release = false;
  return s;
}

std::vector<double> vector_of(const dds_sequence_double& s) {
  if (s._buffer == nullptr) return {};
  return std::vector<double>(s._buffer, s._buffer + s._length);
}

void fill_circle(const Circle& c, stereoball_msg_EyeCircle& out) {
  out.x_px = static_cast<float>(c.x_px);
  out.y_px = static_cast<float>(c.y_px);
  out.radius_px = static_cast<float>(c.radius_px);
  out.score = static_cast<float>(c.score);
}

}  // namespace

Result<stereo::StereoCalibration> from_message(const stereoball_msg_StereoCalibration& msg) {
  if (msg.width_px == 0 || msg.height_px == 0 || msg.width_px > 16384 || msg.height_px > 16384)
    return Error{"image size " + std::to_string(msg.width_px) + "x" +
                 std::to_string(msg.height_px) + " must be in [1, 16384] per side"};
  if (!stereo::is_valid_distortion_size(msg.d1._length))
    return Error{"d1: " + std::to_string(msg.d1._length) +
                 " coefficients, expected 0, 4, 5, 8, 12 or 14"};
  if (!stereo::is_valid_distortion_size(msg.d2._length))
    return Error{"d2: " + std::to_string(msg.d2._length) +
                 " coefficients, expected 0, 4, 5, 8, 12 or 14"};
  stereo::StereoCalibration c;
  c.image_size = cv::Size(static_cast<int>(msg.width_px), static_cast<int>(msg.height_px));
  c.k1 = cv::Matx33d(msg.k1);
  c.d1 = vector_of(msg.d1);
  c.k2 = cv::Matx33d(msg.k2);
  c.d2 = vector_of(msg.d2);
  c.r = cv::Matx33d(msg.r);
  c.t = cv::Vec3d(msg.t[0], msg.t[1], msg.t[2]);
  c.r1 = cv::Matx33d(msg.r1);
  c.r2 = cv::Matx33d(msg.r2);
  c.p1 = cv::Matx34d(msg.p1);
  c.p2 = cv::Matx34d(msg.p2);
  c.q = cv::Matx44d(msg.q);
  c.rms_px = msg.rms_px;
  if (auto e = stereo::validate_calibration(c)) return Error{*e};
  return c;
}

void to_message(const stereo::StereoCalibration& calib, const std::string& source,
                std::int64_t stamp_ns, stereoball_msg_StereoCalibration& msg) {
  msg.stamp_ns = stamp_ns;
  msg.width_px = static_cast<std::uint32_t>(calib.image_size.width);
  msg.height_px = static_cast<std::uint32_t>(calib.image_size.height);
  copy_out(calib.k1, msg.k1);
  msg.d1 = sequence_of(calib.d1);
  copy_out(calib.k2, msg.k2);
  msg.d2 = sequence_of(calib.d2);
  copy_out(calib.r, msg.r);
  std::copy(calib.t.val, calib.t.val + 3, msg.t);
  copy_out(calib.r1, msg.r1);
  copy_out(calib.r2, msg.r2);
  copy_out(calib.p1, msg.p1);
  copy_out(calib.p2, msg.p2);
  copy_out(calib.q, msg.q);
  msg.rms_px = calib.rms_px;
  msg.source = const_cast<char*>(source.c_str());
}

stereoball_msg_DetectionStatus to_message(DetectionStatus status) {
  switch (status) {
    case DetectionStatus::kFound:
      return stereoball_msg_DETECTION_FOUND;
    case DetectionStatus::kNoCandidate:
      return stereoball_msg_DETECTION_NO_CANDIDATE;
    case DetectionStatus::kEpipolarMismatch:
      return stereoball_msg_DETECTION_EPIPOLAR_MISMATCH;
    case DetectionStatus::kSizeInconsistent:
      return stereoball_msg_DETECTION_SIZE_INCONSISTENT;
    case DetectionStatus::kNoCalibration:
      return stereoball_msg_DETECTION_NO_CALIBRATION;
    case DetectionStatus::kBadFrame:
      return stereoball_msg_DETECTION_BAD_FRAME;
  }
  return stereoball_msg_DETECTION_BAD_FRAME;
}

void to_message(const StereoDetection& det, const FrameStamp& frame, float processing_ms,
                std::int64_t publish_stamp_ns, stereoball_msg_BallDetection& msg) {
  msg.frame_seq = frame.seq;
  msg.capture_stamp_ns = frame.stamp_ns;
  msg.publish_stamp_ns = publish_stamp_ns;
  msg.status = to_message(det.status);
  msg.reason = const_cast<char*>(det.reason.c_str());
  fill_circle(det.left, msg.left);
  fill_circle(det.right, msg.right);
  msg.row_residual_px = static_cast<float>(det.row_residual_px);
  const bool found = det.status == DetectionStatus::kFound;
  for (int i = 0; i < 3; ++i) msg.position_m[i] = found ? det.position_m[i] : 0.0;
  msg.depth_from_size_m = static_cast<float>(det.depth_from_size_m);
  msg.candidates_left = static_cast<std::uint32_t>(std::max(det.candidates_left, 0));
  msg.candidates_right = static_cast<std::uint32_t>(std::max(det.candidates_right, 0));
  msg.processing_ms = processing_ms;
  msg.patch_valid = det.patch_valid;
  std::copy(det.patch_rgb.begin(), det.patch_rgb.end(), msg.patch_rgb);
}

TrackedBall from_message(const stereoball_msg_BallTrack& msg) {
  TrackedBall t;
  t.following = msg.state == stereoball_msg_TRACK_FOLLOWING;
  t.position_valid = msg.position_valid;
  t.position_m = {msg.position_m[0], msg.position_m[1], msg.position_m[2]};
  t.velocity_mps = {msg.velocity_mps[0], msg.velocity_mps[1], msg.velocity_mps[2]};
  t.capture_stamp_ns = msg.capture_stamp_ns;
  // A non-finite field (a corrupt sample) must not steer the pairing.
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(t.position_m[i]) || !std::isfinite(t.velocity_mps[i]))
      t.position_valid = false;
  return t;
}

}  // namespace stereoball::ball_detector
