#include "camera_server/core/camera_server_params.hpp"

#include <cmath>

namespace stereoball::camera_server {
namespace {

using params::at;
using params::choice;
using params::flag;
using params::number;
using params::optional;
using params::text;
using P = CameraServerParams;
using C = CameraControls;

Status error(const std::string& message) {
  return Error{message};
}

// 0 leaves the driver's setting; any other temperature must be one a camera can take.
Status check_controls(const C& c) {
  const int32_t k = c.white_balance_temperature_k;
  if (k == 0 || k >= 1000) return {};
  return error(params::out_of_range("controls.white_balance_temperature_k", k, {1000, 15000}, "K",
                                    "or 0 = leave"));
}

// A publish width scales decoded images down: smaller than the capture, even, not tiny.
Status check_publish_width(const P& p) {
  const uint32_t w = p.publish_width_px;
  if (w == 0) return {};
  const std::string key = "key 'publish_width_px': " + std::to_string(w);
  if (w % 2 != 0) return error(key + " must be even (0 = publish as captured)");
  if (w < 16) return error(key + " is below 16 px (0 = publish as captured)");
  if (p.source == "v4l2" && w >= p.width_px) {
    return error(key + " must be smaller than width_px (" + std::to_string(p.width_px) +
                 "): frames are only scaled down (0 = publish as captured)");
  }
  if (p.source == "v4l2" && p.publish_encoding == "native") {
    return error(key +
                 " needs decoded images: set publish_encoding to bgr8 (native yuyv/jpeg "
                 "frames are published as captured and cannot be scaled)");
  }
  return {};
}

// The rules between fields: pixel layout, source-specific inputs, decoded images where needed.
Status check_rules(const P& p) {
  if (p.width_px % 2 != 0) {
    return error("key 'width_px': " + std::to_string(p.width_px) + " must be even");
  }
  if (p.output.compressed() && p.source == "v4l2" && p.publish_encoding == "native") {
    return error("frame_encoding " + p.output.frame_encoding +
                 " needs decoded images: set publish_encoding to bgr8 (native yuyv/jpeg frames "
                 "are published as captured)");
  }
  if (auto st = check_publish_width(p); !st) return st;
  if (auto st = check_controls(p.controls); !st) return st;
  if (p.reopen_max_s < p.reopen_initial_s) {
    return error(params::out_of_range("reopen_max_s", p.reopen_max_s, {p.reopen_initial_s, 600.0},
                                      "s", "at least reopen_initial_s"));
  }
  if (p.source == "files") {
    const bool globs = !p.left_glob.empty() || !p.right_glob.empty();
    if (globs && (p.left_glob.empty() || p.right_glob.empty())) {
      return error("left_glob and right_glob must both be set for the file source");
    }
    if (globs == !p.pairs_dir.empty()) {
      return error("file source needs either left_glob+right_glob or pairs_dir (exactly one)");
    }
  }
  if (p.source == "v4l2" && (p.left_device.empty() || p.right_device.empty())) {
    return error("left_device and right_device must name device nodes, e.g. /dev/video0");
  }
  if (p.source == "v4l2" && p.left_device == p.right_device) {
    return error("left_device and right_device are the same device (" + p.left_device +
                 "); give two different cameras");
  }
  if (p.rectify && p.calibration_file.empty()) return error("rectify needs calibration_file");
  if (p.rectify && p.source == "v4l2" && p.publish_encoding == "native") {
    return error(
        "rectify needs decoded images: set publish_encoding to bgr8 (native yuyv/jpeg frames "
        "cannot be rectified)");
  }
  return {};
}

params::FieldTable<C> make_controls_table() {
  return {{
              optional(flag("controls.auto_exposure", at(&C::auto_exposure), true,
                            "true: the camera picks the exposure; false: exposure_us")),
              optional(number("controls.exposure_us", at(&C::exposure_us), 0, {0, 10'000'000}, "us",
                              "manual exposure, used when auto is off (0 = leave)")),
              optional(number("controls.gain", at(&C::gain), -1, {-1, 100'000}, "",
                              "sensor gain, driver units (-1 = leave)")),
              optional(flag("controls.auto_white_balance", at(&C::auto_white_balance), true,
                            "true: the camera picks the white balance")),
              optional(number("controls.white_balance_temperature_k",
                              at(&C::white_balance_temperature_k), 0, {0, 15'000}, "K",
                              "manual white balance (0 = leave, else at least 1000)")),
          },
          check_controls};
}

std::vector<params::Field<P>> capture_fields() {
  return {
      choice("source", at(&P::source), "v4l2", {"v4l2", "files"},
             "v4l2 (two cameras) or files (image pairs)"),
      optional(text("left_device", at(&P::left_device), "/dev/video0",
                    "left camera node (see `stereoball cameras`)")),
      optional(text("right_device", at(&P::right_device), "/dev/video1",
                    "right camera node; must differ from left_device")),
      number("width_px", at(&P::width_px), 640u, {16, 8192}, "px",
             "capture width (even; for files the images decide, kept for validation)"),
      number("height_px", at(&P::height_px), 480u, {16, 8192}, "px", "capture height"),
      number("rate_hz", at(&P::rate_hz), 30.0, {0.01, 1000.0}, "Hz",
             "capture / playback rate, frames per second"),
      optional(choice("pixel_format", at(&P::pixel_format), "any", {"yuyv", "mjpeg", "any"},
                      "YUYV preferred, MJPEG if YUYV cannot do it")),
      optional(number("max_skew_ns", at(&P::max_skew_ns), 0, {0, 1'000'000'000}, "ns",
                      "largest left/right stamp difference of a pair (0 = half a period)")),
      optional(
          number("buffer_count", at(&P::buffer_count), 4u, {2, 32}, "", "mmap buffers per camera")),
      optional(choice("publish_encoding", at(&P::publish_encoding), "bgr8", {"bgr8", "native"},
                      "bgr8 (converted) or native (yuyv/jpeg as captured)")),
      optional(number("publish_width_px", at(&P::publish_width_px), 0u, {0, 8192}, "px",
                      "each eye scaled (area interpolation) to this width before publishing, "
                      "height in proportion, calibration scaled with it; even, smaller than the "
                      "capture; 0 = as captured")),
  };
}

std::vector<params::Field<P>> source_fields() {
  return {
      optional(number("reopen_initial_s", at(&P::reopen_initial_s), 0.5, {0.001, 60.0}, "s",
                      "first wait before reopening an unplugged camera")),
      optional(number("reopen_max_s", at(&P::reopen_max_s), 8.0, {0.001, 600.0}, "s",
                      "longest wait between reopen attempts (at least reopen_initial_s)")),
      optional(number("reopen_factor", at(&P::reopen_factor), 2.0, {1.0, 10.0}, "",
                      "wait multiplier per failed attempt")),
      optional(number("stall_timeout_s", at(&P::stall_timeout_s), 2.0, {0.1, 600.0}, "s",
                      "a camera silent this long (no error) is reopened")),
      optional(text("left_glob", at(&P::left_glob), "", "file source: glob of left images")),
      optional(text("right_glob", at(&P::right_glob), "", "file source: glob of right images")),
      optional(text("pairs_dir", at(&P::pairs_dir), "",
                    "file source: folder of left*/right* pairs (instead of the globs)")),
      optional(choice("file_encoding", at(&P::file_encoding), "as_read",
                      {"as_read", "bgr8", "mono8"}, "file source: images as read or converted")),
      optional(flag("loop", at(&P::loop), true, "file source: start again after the last pair")),
      optional(text("calibration_file", at(&P::calibration_file), "",
                    "stereo calibration to publish (stereoball-calibrate output; \"\" = none)")),
      optional(flag("rectify", at(&P::rectify), false,
                    "publish rectified images (needs calibration_file)")),
  };
}

params::FieldTable<P> make_table() {
  params::FieldTable<P> t{capture_fields(), check_rules};
  for (const auto& part : {params::section("", &P::output, stereo::frame_codec_fields()),
                           params::section("", &P::controls, camera_controls_fields())}) {
    for (auto f : part.fields) t.fields.push_back(optional(std::move(f)));
  }
  for (auto& f : source_fields()) t.fields.push_back(std::move(f));
  return t;
}

}  // namespace

SB_PARAMS_TABLE(CameraControls, camera_controls_fields, make_controls_table)

SB_PARAMS_TABLE(CameraServerParams, camera_server_fields, make_table)

int64_t CameraServerParams::period_ns() const {
  return static_cast<int64_t>(std::llround(1e9 / rate_hz));
}

int64_t CameraServerParams::effective_skew_ns() const {
  return max_skew_ns > 0 ? max_skew_ns : period_ns() / 2;
}

}  // namespace stereoball::camera_server
