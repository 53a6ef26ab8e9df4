#include "camera_server/node/params_loader.hpp"

#include "common/params/params_file.hpp"

namespace stereoball::camera_server {
namespace {

// Reads key only when present: everything but the capture shape has a default.
template <typename T, typename... Range>
void optional(params::ParamsFile& f, const char* key, T& out, Range... range) {
  if (f.has(key)) f.read(key, out, range...);
}

Result<CameraServerParams> read(params::ParamsFile& f) {
  CameraServerParams p;
  f.read_choice("source", p.source, {"v4l2", "files"});
  f.read("width_px", p.width_px, 16u, 8192u);
  f.read("height_px", p.height_px, 16u, 8192u);
  f.read("rate_hz", p.rate_hz, 0.01, 1000.0);
  optional(f, "left_device", p.left_device);
  optional(f, "right_device", p.right_device);
  if (f.has("pixel_format"))
    f.read_choice("pixel_format", p.pixel_format, {"yuyv", "mjpeg", "any"});
  optional(f, "max_skew_ns", p.max_skew_ns, int64_t{0}, int64_t{1'000'000'000});
  optional(f, "buffer_count", p.buffer_count, 2u, 32u);
  if (f.has("publish_encoding")) {
    f.read_choice("publish_encoding", p.publish_encoding, {"bgr8", "native"});
  }
  if (f.has("frame_encoding")) {
    f.read_choice("frame_encoding", p.output.frame_encoding, frame_encoding_choices());
  }
  optional(f, "jpeg_quality", p.output.jpeg_quality, 1, 100);
  optional(f, "controls.auto_exposure", p.controls.auto_exposure);
  optional(f, "controls.exposure_us", p.controls.exposure_us, 0, 10'000'000);
  optional(f, "controls.gain", p.controls.gain, -1, 100'000);
  optional(f, "controls.auto_white_balance", p.controls.auto_white_balance);
  optional(f, "controls.white_balance_temperature_k", p.controls.white_balance_temperature_k, 0,
           15000);
  optional(f, "reopen_initial_s", p.reopen_initial_s, 0.001, 60.0);
  optional(f, "reopen_max_s", p.reopen_max_s, 0.001, 600.0);
  optional(f, "reopen_factor", p.reopen_factor, 1.0, 10.0);
  optional(f, "stall_timeout_s", p.stall_timeout_s, 0.1, 600.0);
  optional(f, "left_glob", p.left_glob);
  optional(f, "right_glob", p.right_glob);
  optional(f, "pairs_dir", p.pairs_dir);
  if (f.has("file_encoding")) {
    f.read_choice("file_encoding", p.file_encoding, {"as_read", "bgr8", "mono8"});
  }
  optional(f, "loop", p.loop);
  optional(f, "calibration_file", p.calibration_file);
  optional(f, "rectify", p.rectify);
  if (auto e = p.validate()) f.fail(f.name() + ": " + *e);
  if (auto e = f.finish()) return Error{*e};
  return p;
}

}  // namespace

Result<CameraServerParams> load_camera_server_params(const std::string& path) {
  auto f = params::ParamsFile::load(path);
  if (!f) return Error{f.error()};
  return read(*f);
}

Result<CameraServerParams> parse_camera_server_params(const std::string& text,
                                                      const std::string& name) {
  auto f = params::ParamsFile::parse(text, name);
  if (!f) return Error{f.error()};
  return read(*f);
}

}  // namespace stereoball::camera_server
