#include "stereo/frame/frame_msg.hpp"

#include <algorithm>

namespace stereoball::stereo {
void fill_eye_message(const EyeView& v, stereoball_msg_EyeImage& m) {
  m.capture_stamp_ns = v.capture_stamp_ns;
  m.width_px = v.width_px;
  m.height_px = v.height_px;
  m.step_bytes = v.step_bytes;
  m.data._buffer = const_cast<uint8_t*>(v.data);
  m.data._length = static_cast<uint32_t>(v.bytes);
  m.data._maximum = static_cast<uint32_t>(v.bytes);
  m.data._release = false;
}

void fill_frame_message(const FrameView& view, const std::string& source,
                        stereoball_msg_StereoFrame& msg) {
  msg.seq = view.seq;
  msg.stamp_ns = view.stamp_ns;
  msg.source = const_cast<char*>(source.c_str());
  msg.encoding = const_cast<char*>(view.encoding.c_str());
  msg.rectified = view.rectified;
  fill_eye_message(view.left, msg.left);
  fill_eye_message(view.right, msg.right);
}

}  // namespace stereoball::stereo
