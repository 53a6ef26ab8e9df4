#pragma once
// Parameters of the camera server (capture, pairing, controls, file source, reopen back-off).

#include <cstdint>
#include <optional>
#include <string>

#include "camera_server/core/frame_codec.hpp"

namespace stereoball::camera_server {

/// Camera controls applied identically to both cameras; negative/zero values leave a control
/// at the driver's current setting.
struct CameraControls {
  bool auto_exposure = true;                ///< true: camera picks exposure; false: exposure_us
  int32_t exposure_us = 0;                  ///< manual exposure time, microseconds (0 = leave)
  int32_t gain = -1;                        ///< sensor gain, driver units (-1 = leave)
  bool auto_white_balance = true;           ///< true: camera picks white balance
  int32_t white_balance_temperature_k = 0;  ///< manual colour temperature, kelvin (0 = leave)

  /// Names the first bad field and its allowed range, or nullopt.
  std::optional<std::string> validate() const;
};

/// Everything the camera server needs; defaults fit a USB stereo pair at 640x480, 30 Hz.
struct CameraServerParams {
  std::string source = "v4l2";               ///< "v4l2" (two cameras) or "files"
  std::string left_device = "/dev/video0";   ///< left camera device node
  std::string right_device = "/dev/video1";  ///< right camera device node
  uint32_t width_px = 640;                   ///< capture width, pixels
  uint32_t height_px = 480;                  ///< capture height, pixels
  double rate_hz = 30.0;                     ///< capture (or file playback) rate, frames per second
  std::string pixel_format = "any";          ///< "yuyv", "mjpeg" or "any" (YUYV preferred)
  int64_t max_skew_ns = 0;    ///< largest stamp difference of a pair, ns (0 = half a period)
  uint32_t buffer_count = 4;  ///< mmap buffers per camera
  std::string publish_encoding =
      "bgr8";                     ///< "bgr8" (converted) or "native" (yuyv/jpeg as captured)
  FrameCodecParams output;        ///< frame_encoding (raw|jpeg|png) and jpeg_quality
  CameraControls controls;        ///< applied to both cameras
  double reopen_initial_s = 0.5;  ///< first wait before reopening a lost camera, seconds
  double reopen_max_s = 8.0;      ///< longest wait between reopen attempts, seconds
  double reopen_factor = 2.0;     ///< wait multiplier after each failed attempt
  double stall_timeout_s = 2.0;   ///< a streaming camera silent this long is reopened, s
  std::string left_glob;          ///< file source: glob of left images
  std::string right_glob;         ///< file source: glob of right images
  std::string pairs_dir;          ///< file source: folder of left*/right* pairs
  std::string file_encoding = "as_read";  ///< file source: "as_read", "bgr8" or "mono8"
  bool loop = true;                       ///< file source: start again after the last pair
  std::string calibration_file;           ///< stereo calibration to publish (empty = none)
  bool rectify = false;                   ///< publish rectified images (needs calibration_file)

  /// Names the first bad field and its allowed range, or nullopt.
  std::optional<std::string> validate() const;
  /// Pairing skew actually used, ns: max_skew_ns or half a frame period.
  int64_t effective_skew_ns() const;
  /// Frame period, ns.
  int64_t period_ns() const;
};

}  // namespace stereoball::camera_server
