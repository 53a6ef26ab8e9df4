#pragma once
// Test helpers: two scripted cameras offering small YUYV frames.

#include <memory>

#include "camera_server/io/fake_video_device.hpp"
#include "camera_server/io/stereo_capture.hpp"

namespace stereoball::camera_server::testing {

inline constexpr uint32_t kW = 64;
inline constexpr uint32_t kH = 48;
inline constexpr int64_t kPeriodNs = 33'333'333;

/// A camera offering YUYV 64x48@30.
inline std::shared_ptr<FakeCamera> make_camera() {
  auto cam = std::make_shared<FakeCamera>();
  SizeOffer s;
  s.min_width_px = s.max_width_px = kW;
  s.min_height_px = s.max_height_px = kH;
  s.rates_hz = {30.0};
  cam->formats = {{kFourccYuyv, "YUYV 4:2:2", {s}}};
  return cam;
}

/// A YUYV frame whose first byte tags it, stamped at stamp_ns.
inline FakeFrameScript yuyv_frame(int64_t stamp_ns, uint8_t tag) {
  FakeFrameScript f;
  f.stamp_ns = stamp_ns;
  f.bytes.assign(size_t{kW} * kH * 2, 128);
  f.bytes[0] = tag;
  return f;
}

/// Server params matching the fake cameras.
inline CameraServerParams rig_params() {
  CameraServerParams p;
  p.left_device = "/fake/left";
  p.right_device = "/fake/right";
  p.width_px = kW;
  p.height_px = kH;
  p.pixel_format = "yuyv";
  p.reopen_initial_s = 0.5;
  p.reopen_max_s = 4.0;
  return p;
}

/// Factory handing out devices over the two cameras.
inline StereoCapture::DeviceFactory factory(std::shared_ptr<FakeCamera> left,
                                            std::shared_ptr<FakeCamera> right) {
  return [left, right](Eye e) -> std::unique_ptr<VideoDevice> {
    return std::make_unique<FakeVideoDevice>(e == Eye::kLeft ? left : right);
  };
}

}  // namespace stereoball::camera_server::testing
