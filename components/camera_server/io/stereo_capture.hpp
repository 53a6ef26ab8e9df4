#pragma once
// One poll loop over two cameras: dequeues frames, pairs them by capture stamp, survives a
// camera being unplugged (logs, keeps running, reopens with back-off).

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "camera_server/core/camera_server_params.hpp"
#include "camera_server/core/raw_image.hpp"
#include "camera_server/core/reopen_backoff.hpp"
#include "camera_server/core/stereo_pairer.hpp"
#include "camera_server/io/camera_opener.hpp"
#include "camera_server/io/video_device.hpp"

namespace stereoball::camera_server {

/// Health of one camera.
struct EyeHealth {
  std::string path;
  bool streaming = false;
  ActiveFormat format;
  uint64_t frames = 0;     ///< frames dequeued
  uint64_t corrupted = 0;  ///< frames the driver flagged or that were too short
  uint64_t errors = 0;     ///< device errors (each loss counts once)
  uint64_t reopens = 0;    ///< successful reopens after a loss
  std::string last_error;
};

/// Health of the capture: both cameras and the pairing.
struct CaptureHealth {
  std::array<EyeHealth, 2> eyes;  ///< indexed by Eye
  PairerStats pairing;
};

/// The capture loop over two VideoDevices.
class StereoCapture {
 public:
  /// Makes a fresh device object for an eye (V4l2Device in production, fakes in tests).
  using DeviceFactory = std::function<std::unique_ptr<VideoDevice>(Eye)>;

  StereoCapture(const CameraServerParams& params, DeviceFactory factory);

  /// Opens and starts both cameras; the error names the device and the problem.
  DeviceStatus start();
  /// Waits up to timeout_ms for frames and returns the pairs completed; reopens lost cameras
  /// when their back-off (driven by now_ns, ns) has elapsed.
  std::vector<RawStereoPair> poll_once(int timeout_ms, int64_t now_ns);
  /// Log lines produced since the last call (losses, reopen attempts, control warnings).
  std::vector<std::string> take_log();
  /// Counters and state of both cameras.
  CaptureHealth health() const;
  /// True while both cameras stream.
  bool healthy() const;

 private:
  struct EyeState {
    std::unique_ptr<VideoDevice> device;
    CameraConfig config;
    EyeHealth health;
    ReopenBackoff backoff;
    int64_t last_frame_ns = -1;  ///< -1 until the first poll after (re)opening
  };

  void lose(Eye eye, const DeviceStatus& status, int64_t now_ns);
  void try_reopen(Eye eye, int64_t now_ns);
  void drain(Eye eye, int64_t now_ns, std::vector<RawStereoPair>& pairs);
  void check_stall(Eye eye, int64_t now_ns);
  DeviceStatus open_eye(Eye eye);
  EyeState& state(Eye eye) { return eyes_[static_cast<int>(eye)]; }

  CameraServerParams params_;
  DeviceFactory factory_;
  std::array<EyeState, 2> eyes_;
  StereoPairer<RawImage> pairer_;
  std::vector<std::string> log_;
};

}  // namespace stereoball::camera_server
