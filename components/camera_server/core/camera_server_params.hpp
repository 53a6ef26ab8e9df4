#pragma once
// Parameters of the camera server (capture, pairing, controls, file source, reopen back-off).

#include <cstdint>
#include <string>

#include "common/params/field_table.hpp"
#include "common/util/result.hpp"
#include "stereo/frame/frame_codec.hpp"

namespace stereoball::camera_server {

/// Camera controls applied identically to both cameras; negative/zero values leave a control
/// at the driver's current setting. Defaults, ranges, units: camera_controls_fields().
struct CameraControls {
  CameraControls();         ///< every field at its default from camera_controls_fields()
  bool auto_exposure;       ///< true: camera picks exposure; false: exposure_us
  int32_t exposure_us;      ///< manual exposure time (0 = leave)
  int32_t gain;             ///< sensor gain, driver units (-1 = leave)
  bool auto_white_balance;  ///< true: camera picks white balance
  int32_t white_balance_temperature_k;  ///< manual colour temperature (0 = leave)

  /// Success, or the first field out of its range, naming key and range.
  Status validate() const;
};

/// The controls.* keys of the camera_server file.
const params::FieldTable<CameraControls>& camera_controls_fields();

/// Everything the camera server needs; defaults fit a USB stereo pair at 640x480, 30 Hz. Each
/// field's key, default, range, unit and meaning: camera_server_fields().
struct CameraServerParams {
  CameraServerParams();  ///< every field at its default from camera_server_fields()
  std::string source;
  std::string left_device;
  std::string right_device;
  uint32_t width_px;
  uint32_t height_px;
  double rate_hz;
  std::string pixel_format;
  int64_t max_skew_ns;
  uint32_t buffer_count;
  std::string publish_encoding;
  uint32_t publish_width_px;  ///< eyes scaled to this width before publishing (0 = as captured)
  stereo::FrameCodecParams output;  ///< frame_encoding (raw|jpeg|png) and jpeg_quality
  CameraControls controls;          ///< applied to both cameras
  double reopen_initial_s;
  double reopen_max_s;
  double reopen_factor;
  double stall_timeout_s;
  std::string left_glob;
  std::string right_glob;
  std::string pairs_dir;
  std::string file_encoding;
  bool loop;
  std::string calibration_file;
  bool rectify;

  /// Success, or the first field out of its range or rule broken, naming the key.
  Status validate() const;
  /// Pairing skew actually used, ns: max_skew_ns or half a frame period.
  int64_t effective_skew_ns() const;
  /// Frame period, ns.
  int64_t period_ns() const;
};

/// One row per parameter of config/camera_server*.yaml: the capture shape (source, width_px,
/// height_px, rate_hz) is required, every other key optional (a file source needs no camera
/// settings and the reverse). Drives the defaults, validate(), the loader, the README table
/// and `camera_server --help-params`.
const params::FieldTable<CameraServerParams>& camera_server_fields();

}  // namespace stereoball::camera_server
