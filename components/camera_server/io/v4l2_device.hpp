#pragma once
// VideoDevice over real V4L2 ioctls with memory-mapped streaming.

#include <vector>

#include "camera_server/io/video_device.hpp"

namespace stereoball::camera_server {

/// Production VideoDevice: one /dev/videoN node.
class V4l2Device final : public VideoDevice {
 public:
  V4l2Device() = default;
  ~V4l2Device() override;
  V4l2Device(const V4l2Device&) = delete;
  V4l2Device& operator=(const V4l2Device&) = delete;

  DeviceStatus open(const std::string& path) override;
  void close() override;
  DeviceStatus query_caps(DeviceCaps& caps) override;
  DeviceStatus enumerate_formats(std::vector<FormatOffer>& formats) override;
  DeviceStatus set_format(const FormatChoice& choice, ActiveFormat& active) override;
  DeviceStatus set_control(const ControlSetting& control) override;
  DeviceStatus start_streaming(uint32_t buffer_count) override;
  int poll_fd() const override { return fd_; }
  DeviceStatus dequeue(DequeuedFrame& frame) override;
  DeviceStatus requeue(uint32_t index) override;

 private:
  struct Buffer {
    void* start = nullptr;
    size_t length = 0;
  };
  DeviceStatus error(const char* operation) const;
  void enumerate_sizes(uint32_t fourcc, FormatOffer& offer);
  std::vector<double> enumerate_rates(uint32_t fourcc, uint32_t w, uint32_t h);
  void release_buffers();

  std::string path_;
  int fd_ = -1;
  bool streaming_ = false;
  std::vector<Buffer> buffers_;
};

}  // namespace stereoball::camera_server
