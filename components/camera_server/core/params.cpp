#include "camera_server/core/params.hpp"

#include <cmath>

namespace stereoball::camera_server {

std::optional<std::string> CameraControls::validate() const {
  if (exposure_us < 0 || exposure_us > 10'000'000) {
    return "controls.exposure_us must be in [0, 10000000] (0 = leave), got " +
           std::to_string(exposure_us);
  }
  if (gain < -1 || gain > 100'000) {
    return "controls.gain must be in [-1, 100000] (-1 = leave), got " + std::to_string(gain);
  }
  if (white_balance_temperature_k != 0 &&
      (white_balance_temperature_k < 1000 || white_balance_temperature_k > 15000)) {
    return "controls.white_balance_temperature_k must be 0 (leave) or in [1000, 15000], got " +
           std::to_string(white_balance_temperature_k);
  }
  return std::nullopt;
}

namespace {

bool one_of(const std::string& v, std::initializer_list<const char*> allowed) {
  for (const char* a : allowed) {
    if (v == a) return true;
  }
  return false;
}

}  // namespace

std::optional<std::string> CameraServerParams::validate() const {
  if (!one_of(source, {"v4l2", "files"})) {
    return "source must be \"v4l2\" or \"files\", got \"" + source + "\"";
  }
  if (width_px < 16 || width_px > 8192 || width_px % 2 != 0) {
    return "width_px must be even and in [16, 8192], got " + std::to_string(width_px);
  }
  if (height_px < 16 || height_px > 8192) {
    return "height_px must be in [16, 8192], got " + std::to_string(height_px);
  }
  if (!std::isfinite(rate_hz) || rate_hz <= 0.0 || rate_hz > 1000.0) {
    return "rate_hz must be in (0, 1000], got " + std::to_string(rate_hz);
  }
  if (!one_of(pixel_format, {"yuyv", "mjpeg", "any"})) {
    return "pixel_format must be \"yuyv\", \"mjpeg\" or \"any\", got \"" + pixel_format + "\"";
  }
  if (max_skew_ns < 0 || max_skew_ns > 1'000'000'000) {
    return "max_skew_ns must be in [0, 1000000000] (0 = half a frame period), got " +
           std::to_string(max_skew_ns);
  }
  if (buffer_count < 2 || buffer_count > 32) {
    return "buffer_count must be in [2, 32], got " + std::to_string(buffer_count);
  }
  if (!one_of(publish_encoding, {"bgr8", "native"})) {
    return "publish_encoding must be \"bgr8\" or \"native\", got \"" + publish_encoding + "\"";
  }
  if (auto e = output.validate()) return e;
  if (output.compressed() && source == "v4l2" && publish_encoding == "native") {
    return "frame_encoding " + output.frame_encoding +
           " needs decoded images: set publish_encoding to bgr8 (native yuyv/jpeg frames are "
           "published as captured)";
  }
  if (auto e = controls.validate()) return e;
  if (!(reopen_initial_s > 0.0 && reopen_initial_s <= 60.0)) {
    return "reopen_initial_s must be in (0, 60], got " + std::to_string(reopen_initial_s);
  }
  if (!(reopen_max_s >= reopen_initial_s && reopen_max_s <= 600.0)) {
    return "reopen_max_s must be in [reopen_initial_s, 600], got " + std::to_string(reopen_max_s);
  }
  if (!(reopen_factor >= 1.0 && reopen_factor <= 10.0)) {
    return "reopen_factor must be in [1, 10], got " + std::to_string(reopen_factor);
  }
  if (!(stall_timeout_s >= 0.1 && stall_timeout_s <= 600.0)) {
    return "stall_timeout_s must be in [0.1, 600], got " + std::to_string(stall_timeout_s);
  }
  if (!one_of(file_encoding, {"as_read", "bgr8", "mono8"})) {
    return "file_encoding must be \"as_read\", \"bgr8\" or \"mono8\", got \"" + file_encoding +
           "\"";
  }
  if (source == "files") {
    const bool globs = !left_glob.empty() || !right_glob.empty();
    if (globs && (left_glob.empty() || right_glob.empty())) {
      return "left_glob and right_glob must both be set for the file source";
    }
    if (globs == !pairs_dir.empty()) {
      return "file source needs either left_glob+right_glob or pairs_dir (exactly one)";
    }
  }
  if (source == "v4l2" && (left_device.empty() || right_device.empty())) {
    return "left_device and right_device must name device nodes, e.g. /dev/video0";
  }
  if (source == "v4l2" && left_device == right_device) {
    return "left_device and right_device are the same device (" + left_device +
           "); give two different cameras";
  }
  if (rectify && calibration_file.empty()) {
    return "rectify needs calibration_file";
  }
  if (rectify && source == "v4l2" && publish_encoding == "native") {
    return "rectify needs decoded images: set publish_encoding to bgr8 (native yuyv/jpeg "
           "frames cannot be rectified)";
  }
  return std::nullopt;
}

int64_t CameraServerParams::period_ns() const {
  return static_cast<int64_t>(std::llround(1e9 / rate_hz));
}

int64_t CameraServerParams::effective_skew_ns() const {
  return max_skew_ns > 0 ? max_skew_ns : period_ns() / 2;
}

}  // namespace stereoball::camera_server
