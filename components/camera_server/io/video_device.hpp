#pragma once
// Thin interface over one V4L2 capture device: the seam between the capture logic and the
// ioctls. V4l2Device is the real implementation; FakeVideoDevice replays scripts in tests.

#include <cstdint>
#include <string>
#include <vector>

#include "camera_server/core/camera_controls.hpp"
#include "camera_server/core/format_negotiation.hpp"

namespace stereoball::camera_server {

/// Outcome of a device operation: err is the errno (0 = success), message one clear line.
struct DeviceStatus {
  int err = 0;
  std::string message;
  bool ok() const { return err == 0 && message.empty(); }
};

/// What VIDIOC_QUERYCAP reports.
struct DeviceCaps {
  std::string driver;
  std::string card;  ///< human name of the camera
  std::string bus_info;
  bool video_capture = false;  ///< single-planar video capture supported
  bool streaming = false;      ///< streaming I/O (mmap) supported
};

/// The format the driver actually configured.
struct ActiveFormat {
  uint32_t fourcc = 0;
  uint32_t width_px = 0;
  uint32_t height_px = 0;
  uint32_t step_bytes = 0;   ///< bytes per row (0 for compressed formats)
  uint32_t image_bytes = 0;  ///< largest frame size, bytes
};

/// One dequeued buffer; data stays valid until requeue(index).
struct DequeuedFrame {
  const uint8_t* data = nullptr;
  size_t bytes = 0;
  int64_t stamp_ns = 0;    ///< capture stamp, ns since the Unix epoch
  uint32_t sequence = 0;   ///< driver frame counter
  uint32_t index = 0;      ///< buffer index for requeue
  bool corrupted = false;  ///< driver flagged the buffer as erroneous
};

/// One capture device. All calls are non-blocking; wait for frames by polling poll_fd().
class VideoDevice {
 public:
  virtual ~VideoDevice() = default;
  /// Opens the device node.
  virtual DeviceStatus open(const std::string& path) = 0;
  /// Stops streaming, unmaps buffers and closes; safe to call twice.
  virtual void close() = 0;
  /// VIDIOC_QUERYCAP.
  virtual DeviceStatus query_caps(DeviceCaps& caps) = 0;
  /// Capture formats with their frame sizes and rates (ENUM_FMT/FRAMESIZES/FRAMEINTERVALS).
  virtual DeviceStatus enumerate_formats(std::vector<FormatOffer>& formats) = 0;
  /// S_FMT + S_PARM; fails when the driver substitutes another format or size.
  virtual DeviceStatus set_format(const FormatChoice& choice, ActiveFormat& active) = 0;
  /// VIDIOC_S_CTRL.
  virtual DeviceStatus set_control(const ControlSetting& control) = 0;
  /// REQBUFS, mmap, QBUF every buffer, STREAMON.
  virtual DeviceStatus start_streaming(uint32_t buffer_count) = 0;
  /// File descriptor that becomes readable when a frame is ready (-1 when closed).
  virtual int poll_fd() const = 0;
  /// VIDIOC_DQBUF; err == EAGAIN when no frame is ready.
  virtual DeviceStatus dequeue(DequeuedFrame& frame) = 0;
  /// VIDIOC_QBUF of a dequeued buffer.
  virtual DeviceStatus requeue(uint32_t index) = 0;
};

}  // namespace stereoball::camera_server
