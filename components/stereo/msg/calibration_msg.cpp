#include "stereo/msg/calibration_msg.hpp"

#include <algorithm>

namespace stereoball::stereo {
namespace {

template <int R, int C>
void copy_out(const cv::Matx<double, R, C>& m, double* out) {
  std::copy(m.val, m.val + R * C, out);
}

dds_sequence_double borrowed_sequence(const std::vector<double>& v) {
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

std::string distortion_error(const char* name, std::uint32_t length) {
  return std::string(name) + ": " + std::to_string(length) +
         " coefficients, expected 0, 4, 5, 8, 12 or 14";
}

}  // namespace

stereoball_msg_StereoCalibration calibration_to_message(const StereoCalibration& calib,
                                                        std::int64_t stamp_ns,
                                                        const std::string& source) {
  stereoball_msg_StereoCalibration msg{};
  msg.stamp_ns = stamp_ns;
  msg.width_px = static_cast<std::uint32_t>(calib.image_size.width);
  msg.height_px = static_cast<std::uint32_t>(calib.image_size.height);
  copy_out(calib.k1, msg.k1);
  msg.d1 = borrowed_sequence(calib.d1);
  copy_out(calib.k2, msg.k2);
  msg.d2 = borrowed_sequence(calib.d2);
  copy_out(calib.r, msg.r);
  std::copy(calib.t.val, calib.t.val + 3, msg.t);
  copy_out(calib.r1, msg.r1);
  copy_out(calib.r2, msg.r2);
  copy_out(calib.p1, msg.p1);
  copy_out(calib.p2, msg.p2);
  copy_out(calib.q, msg.q);
  msg.rms_px = calib.rms_px;
  msg.source = const_cast<char*>(source.c_str());
  return msg;
}

::stereoball::Result<StereoCalibration> calibration_from_message(
    const stereoball_msg_StereoCalibration& msg, cv::Size max_size) {
  using ::stereoball::Error;
  if (msg.width_px == 0 || msg.height_px == 0 ||
      msg.width_px > static_cast<std::uint32_t>(std::max(max_size.width, 0)) ||
      msg.height_px > static_cast<std::uint32_t>(std::max(max_size.height, 0)))
    return Error{"image size " + std::to_string(msg.width_px) + "x" +
                 std::to_string(msg.height_px) + " is outside the limit 1x1 .. " +
                 std::to_string(max_size.width) + "x" + std::to_string(max_size.height)};
  if (!is_valid_distortion_size(msg.d1._length))
    return Error{distortion_error("d1", msg.d1._length)};
  if (!is_valid_distortion_size(msg.d2._length))
    return Error{distortion_error("d2", msg.d2._length)};
  StereoCalibration c;
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
  if (auto e = validate_calibration(c); !e) return Error{e.error()};
  return c;
}

}  // namespace stereoball::stereo
