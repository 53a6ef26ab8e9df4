#pragma once
// Scripted VideoDevice for tests: replays frames and errno values, and can simulate a camera
// that is unplugged mid-stream and comes back after some failed reopen attempts.

#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "camera_server/io/video_device.hpp"

namespace stereoball::camera_server {

/// One scripted dequeue: a frame, or an errno (e.g. ENODEV for an unplug).
struct FakeFrameScript {
  int64_t stamp_ns = 0;
  std::vector<uint8_t> bytes;
  int err = 0;  ///< non-zero: dequeue fails with this errno instead of returning a frame
};

/// The "physical" camera; it outlives FakeVideoDevice instances so reopening sees its state.
/// push() and queued() may be called while a device streams (a test feeding a live stream).
struct FakeCamera {
  DeviceCaps caps{"fake", "Fake Camera", "fake:0", true, true};
  std::vector<FormatOffer> formats;
  int open_errno = 0;                 ///< errno every open() fails with (0 = opens)
  int failed_opens_after_unplug = 0;  ///< opens failing with ENOENT after a scripted ENODEV
  std::deque<FakeFrameScript> script;
  // Observations for tests.
  int opens = 0;
  int streams_started = 0;
  std::vector<ControlSetting> controls_set;
  std::vector<FormatChoice> formats_set;

  /// Appends a frame (and wakes a streaming device).
  void push(FakeFrameScript f);
  /// Scripted dequeues not yet taken.
  size_t queued();
  std::mutex mutex;   ///< guards script and event_fd against a streaming device's thread
  int event_fd = -1;  ///< set while a device streams; readable while frames are queued
  int unplugged_opens_left = 0;
};

/// VideoDevice over a FakeCamera.
class FakeVideoDevice final : public VideoDevice {
 public:
  explicit FakeVideoDevice(std::shared_ptr<FakeCamera> camera);
  ~FakeVideoDevice() override;

  DeviceStatus open(const std::string& path) override;
  void close() override;
  DeviceStatus query_caps(DeviceCaps& caps) override;
  DeviceStatus enumerate_formats(std::vector<FormatOffer>& formats) override;
  DeviceStatus set_format(const FormatChoice& choice, ActiveFormat& active) override;
  DeviceStatus set_control(const ControlSetting& control) override;
  DeviceStatus start_streaming(uint32_t buffer_count) override;
  int poll_fd() const override { return event_fd_; }
  DeviceStatus dequeue(DequeuedFrame& frame) override;
  DeviceStatus requeue(uint32_t index) override;

 private:
  std::shared_ptr<FakeCamera> camera_;
  std::string path_;
  bool open_ = false;
  int event_fd_ = -1;
  ActiveFormat active_;
  FakeFrameScript current_;
  bool holding_ = false;
};

}  // namespace stereoball::camera_server
