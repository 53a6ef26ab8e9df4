#include "camera_server/node/frame_message.hpp"

#include <algorithm>

namespace stereoball::camera_server {
namespace {

void fill_eye(const EyeView& v, stereoball_msg_EyeImage& m) {
  m.capture_stamp_ns = v.capture_stamp_ns;
  m.width_px = v.width_px;
  m.height_px = v.height_px;
  m.step_bytes = v.step_bytes;
  m.data._buffer = const_cast<uint8_t*>(v.data);
  m.data._length = static_cast<uint32_t>(v.bytes);
  m.data._maximum = static_cast<uint32_t>(v.bytes);
  m.data._release = false;
}

template <typename Matx>
void copy_matrix(const Matx& m, double* out) {
  std::copy(m.val, m.val + Matx::rows * Matx::cols, out);
}

template <typename Seq>
void point_at(const std::vector<double>& v, Seq& seq) {
  seq._buffer = const_cast<double*>(v.data());
  seq._length = static_cast<uint32_t>(std::min<size_t>(v.size(), 14));
  seq._maximum = seq._length;
  seq._release = false;
}

}  // namespace

void fill_frame_message(const FrameView& view, const std::string& source,
                        stereoball_msg_StereoFrame& msg) {
  msg.seq = view.seq;
  msg.stamp_ns = view.stamp_ns;
  msg.source = const_cast<char*>(source.c_str());
  msg.encoding = const_cast<char*>(view.encoding.c_str());
  msg.rectified = view.rectified;
  fill_eye(view.left, msg.left);
  fill_eye(view.right, msg.right);
}

void fill_calibration_message(const stereo::StereoCalibration& c, const std::string& source,
                              int64_t stamp_ns, stereoball_msg_StereoCalibration& msg) {
  msg.stamp_ns = stamp_ns;
  msg.width_px = static_cast<uint32_t>(c.image_size.width);
  msg.height_px = static_cast<uint32_t>(c.image_size.height);
  copy_matrix(c.k1, msg.k1);
  copy_matrix(c.k2, msg.k2);
  point_at(c.d1, msg.d1);
  point_at(c.d2, msg.d2);
  copy_matrix(c.r, msg.r);
  std::copy(c.t.val, c.t.val + 3, msg.t);
  copy_matrix(c.r1, msg.r1);
  copy_matrix(c.r2, msg.r2);
  copy_matrix(c.p1, msg.p1);
  copy_matrix(c.p2, msg.p2);
  copy_matrix(c.q, msg.q);
  msg.rms_px = c.rms_px;
  msg.source = const_cast<char*>(source.c_str());
}

}  // namespace stereoball::camera_server
