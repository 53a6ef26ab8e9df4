#include "camera_server/node/camera_server_node.hpp"

#include <span>

#include "camera_server/core/format_negotiation.hpp"
#include "camera_server/io/v4l2_device.hpp"
#include "camera_server/node/rectify_input.hpp"
#include "common/dds/shared_memory.hpp"
#include "common/util/log.hpp"
#include "stereo/core/calibration_scaling.hpp"
#include "stereo/core/eye_order.hpp"
#include "stereo/frame/eye_pixels.hpp"
#include "stereo/frame/frame_msg.hpp"
#include "stereo/image/image_decode.hpp"
#include "stereo/io/calibration_file.hpp"
#include "stereo/msg/calibration_msg.hpp"

namespace stereoball::camera_server {
namespace {

// The fix for cameras in the wrong order, in this node's terms.
constexpr const char* kHowToSwap =
    "swap left_device and right_device in the camera_server config (file source: left_glob and "
    "right_glob)";

std::string size_text(cv::Size s) {
  return std::to_string(s.width) + "x" + std::to_string(s.height);
}

// The pixels of one eye for the eye-order check: raw eyes as they are or converted (yuyv), native
// MJPEG decoded, its header first checked against the frame's size (as a decoder of untrusted
// bytes must).
Result<cv::Mat> eye_order_pixels(const stereo::EyeView& eye, const std::string& encoding,
                                 cv::Mat& storage) {
  if (encoding != "jpeg") return stereo::eye_pixels(eye, encoding, storage);
  const std::span<const uint8_t> bytes(eye.data, eye.data == nullptr ? 0 : eye.bytes);
  const auto header = stereo::read_image_header(bytes);
  if (!header) return Error{header.error()};
  const cv::Size size(static_cast<int>(eye.width_px), static_cast<int>(eye.height_px));
  if (auto st = stereo::check_within(*header, size); !st) return Error{st.error()};
  if (auto st = stereo::decode_bgr(bytes, *header, storage); !st) return Error{st.error()};
  return storage;
}

}  // namespace

CameraServerNode::CameraServerNode(const CameraServerParams& params, node::Runner& runner)
    : params_(params),
      runner_(runner),
      frame_writer_(runner.participant(), topics::kStereoFrame),
      calibration_writer_(runner.participant(), topics::kStereoCalibration),
      builder_(FrameBuilderParams{params.publish_encoding}) {
  if (params.output.compressed()) compressor_.emplace(params.output);
}

CameraServerNode::~CameraServerNode() {
  stop_ = true;
  if (capture_thread_.joinable()) capture_thread_.join();
}

Result<std::unique_ptr<CameraServerNode>> CameraServerNode::create(
    const CameraServerParams& params, node::Runner& runner, StereoCapture::DeviceFactory devices) {
  if (auto st = params.validate(); !st) return Error{st.error()};
  std::unique_ptr<CameraServerNode> node(new CameraServerNode(params, runner));
  if (auto st = node->open_source(std::move(devices)); !st) return Error{st.error()};
  node->start();
  return node;
}

Status CameraServerNode::open_source(StereoCapture::DeviceFactory devices) {
  cv::Size size(static_cast<int>(params_.width_px), static_cast<int>(params_.height_px));
  if (params_.source == "files") {
    auto src = FileSource::open(FileSourceParams{params_.left_glob, params_.right_glob,
                                                 params_.pairs_dir, params_.file_encoding});
    if (!src) return Error{src.error()};
    files_.emplace(std::move(*src));
    source_name_ = files_->description();
    size = files_->image_size();
    log::info("file source: ", files_->size(), " pairs, ", size_text(size), " ", files_->encoding(),
              ", ", params_.rate_hz, " Hz");
    if (auto st = open_scaler(size); !st) return st;
    if (auto st = open_calibration(size); !st) return st;
    check_transport(files_->encoding());
    return {};
  }
  source_name_ = "v4l2:" + params_.left_device + "+" + params_.right_device;
  if (!devices) devices = [](Eye) { return std::make_unique<V4l2Device>(); };
  capture_ = std::make_unique<StereoCapture>(params_, std::move(devices));
  // Check the calibration before touching the cameras: a wrong size is a config error.
  if (auto st = open_scaler(size); !st) return st;
  if (auto st = open_calibration(size); !st) return st;
  const DeviceStatus st = capture_->start();
  if (!st.ok()) return Error{st.message};
  for (const auto& line : capture_->take_log()) log::warn(line);
  const auto h = capture_->health();
  log::info("streaming ", source_name_, " as ", fourcc_text(h.eyes[0].format.fourcc), " ",
            size_text(size), " at ", params_.rate_hz, " Hz");
  const bool native = params_.publish_encoding == "native";
  check_transport(!native ? "bgr8" : h.eyes[0].format.fourcc == kFourccYuyv ? "yuyv" : "jpeg");
  return {};
}

Status CameraServerNode::open_scaler(cv::Size capture_size) {
  publish_size_ = capture_size;
  const uint32_t w = params_.publish_width_px;
  if (w == 0) return {};
  if (w >= static_cast<uint32_t>(capture_size.width)) {
    return Error{"key 'publish_width_px': " + std::to_string(w) +
                 " must be smaller than the captured width (" + size_text(capture_size) +
                 "): frames are only scaled down (0 = publish as captured)"};
  }
  scaler_.emplace(static_cast<int>(w));
  publish_size_ = scaler_->output_size(capture_size);
  log::info("publishing ", size_text(publish_size_), " eyes scaled from ", size_text(capture_size),
            " (publish_width_px)", params_.calibration_file.empty() ? "" : " with the calibration");
  return {};
}

// Raw frames have a known size: compare it with the receive buffer once, at start. Compressed
// frames are checked as they are published (check_sample).
void CameraServerNode::check_transport(const std::string& raw_encoding) {
  transport_ = stereo::read_transport_limits(
      {dds::ensure_shared_memory_usable() == dds::SharedMemoryState::kOn,
       runner_.participant().built_in_config()});
  runner_.health().set_counter("receive_buffer_bytes", transport_.receive_buffer_bytes());
  if (params_.output.compressed() || raw_encoding == "jpeg") return;
  const uint64_t bytes_per_px = raw_encoding == "bgr8" ? 3 : raw_encoding == "yuyv" ? 2 : 1;
  const uint64_t eye = static_cast<uint64_t>(publish_size_.area()) * bytes_per_px;
  const uint64_t sample = stereo::frame_sample_bytes(eye, eye);
  runner_.health().set_counter("frame_sample_bytes", sample);
  report_oversize(sample, "raw " + size_text(publish_size_) + " " + raw_encoding + " frames");
}

void CameraServerNode::report_oversize(uint64_t sample_bytes, const std::string& what) {
  if (oversize_reported_) return;
  const auto warning = stereo::oversize_warning(sample_bytes, transport_, what);
  if (!warning) return;
  oversize_reported_ = true;
  log::warn(*warning);
  runner_.health().error("frame_too_large", *warning);
}

void CameraServerNode::check_sample(const stereo::FrameView& view) {
  const uint64_t sample = stereo::frame_sample_bytes(view.left.bytes, view.right.bytes);
  if (sample <= largest_sample_bytes_) return;
  largest_sample_bytes_ = sample;
  runner_.health().set_counter("frame_sample_bytes", sample);
  report_oversize(sample,
                  view.encoding + " " + size_text(publish_size_) + " frames (largest so far)");
}

Result<CameraServerNode::LoadedCalibration> CameraServerNode::load_calibration_file(
    cv::Size capture_size) const {
  auto calib = stereo::load_calibration(params_.calibration_file);
  if (!calib) return Error{calib.error()};
  if (calib->image_size != capture_size) {
    return Error{"calibration " + params_.calibration_file + " is for " +
                 size_text(calib->image_size) + " images but the capture size is " +
                 size_text(capture_size) +
                 "; recalibrate at this size or change width_px/height_px"};
  }
  if (auto swapped = stereo::check_camera_order(*calib); !swapped) {
    return Error{"calibration " + params_.calibration_file + ": " + swapped.error() + "; " +
                 kHowToSwap + " and calibrate again (stereoball calibrate)"};
  }
  if (scaler_) {
    auto scaled = stereo::scale_calibration(*calib, publish_size_);
    if (!scaled) return Error{params_.calibration_file + ": " + scaled.error()};
    calib = std::move(scaled);
  }
  // Also without `rectify`: the eye-order check of the first frames rectifies them (at the
  // published size: frames are scaled before they are rectified).
  auto r = stereo::Rectifier::create(*calib);
  if (!r) return Error{params_.calibration_file + ": " + r.error()};
  return LoadedCalibration{std::move(calib).value(), std::move(r).value()};
}

Status CameraServerNode::open_calibration(cv::Size capture_size) {
  capture_size_ = capture_size;
  if (params_.calibration_file.empty()) return {};
  std::error_code ec;
  calibration_mtime_ = std::filesystem::last_write_time(params_.calibration_file, ec);
  auto loaded = load_calibration_file(capture_size);
  if (!loaded) return Error{loaded.error()};
  calibration_.emplace(std::move(loaded->calibration));
  rectifier_.emplace(std::move(loaded->rectifier));
  return {};
}

void CameraServerNode::publish_calibration() {
  const std::string source =
      scaler_ ? params_.calibration_file + " scaled to " + size_text(publish_size_)
              : params_.calibration_file;
  calibration_writer_.write(stereo::calibration_to_message(*calibration_, node::now_ns(), source));
  runner_.health().count(std::string(topics::kStereoCalibration.spec.name));
}

// Runner thread, once a second: a calibration file written since it was read (a new
// calibration from stereoball calibrate live) is checked as at start and published; a bad
// one is reported once and the calibration in use kept.
void CameraServerNode::reload_calibration_if_changed() {
  std::error_code ec;
  const auto mtime = std::filesystem::last_write_time(params_.calibration_file, ec);
  if (ec || mtime == calibration_mtime_) return;
  calibration_mtime_ = mtime;
  auto loaded = load_calibration_file(capture_size_);
  if (!loaded) {
    const std::string text =
        "calibration file changed but not used (the old one stays): " + loaded.error();
    log::warn(text);
    runner_.health().error("calibration_reload", text);
    return;
  }
  {
    std::lock_guard lock(calibration_mutex_);
    calibration_.emplace(std::move(loaded->calibration));
    rectifier_.emplace(std::move(loaded->rectifier));
    eye_order_.reset();  // judge the eye order again with the new file
    eye_order_skipped_.clear();
    publish_calibration();
  }
  log::info("calibration reloaded from ", params_.calibration_file, " and published");
}

void CameraServerNode::start() {
  if (compressor_) {
    log::info("publishing ", params_.output.frame_encoding, " frames",
              params_.output.frame_encoding == "jpeg"
                  ? " at quality " + std::to_string(params_.output.jpeg_quality) + ", chroma " +
                        params_.output.jpeg_chroma
                  : std::string());
  }
  if (!calibration_) log::warn("no calibration_file: stereo/calibration is not published");
  if (calibration_) {
    publish_calibration();
    runner_.every(1'000'000'000, [this](int64_t) { reload_calibration_if_changed(); });
  }
  if (files_) {
    runner_.every(params_.period_ns(), [this](int64_t now_ns) { publish_file_pair(now_ns); });
    runner_.health().set_state(true, "playing files");
    return;
  }
  runner_.health().set_state(true, "streaming");
  capture_thread_ = std::thread([this] { capture_loop(); });
}

void CameraServerNode::publish_file_pair(int64_t now_ns) {
  if (files_done_) return;
  const size_t i = file_seq_ % files_->size();
  if (!params_.loop && file_seq_ >= files_->size()) {
    files_done_ = true;
    runner_.health().set_state(true, "file source finished");
    log::info("file source finished after ", file_seq_, " pairs (loop: false)");
    return;
  }
  const FilePair& p = files_->pair(i);
  auto view = stereo::view_of_images(p.left, p.right, file_seq_++, now_ns);
  if (!view) {
    runner_.health().error("bad_file_pair", view.error());
    return;
  }
  publish(*view);
}

void CameraServerNode::capture_loop() {
  while (!stop_ && !runner_.stopping()) {
    auto pairs = capture_->poll_once(100, node::monotonic_ns());
    for (const auto& line : capture_->take_log()) {
      log::warn(line);
      if (line.find(" lost: ") != std::string::npos) runner_.health().error("camera_lost", line);
    }
    for (const auto& pair : pairs) {
      skew_.add(pair.left_stamp_ns, pair.right_stamp_ns);
      auto view = builder_.step(pair);
      if (!view) {
        runner_.health().error("bad_frame", view.error());
        continue;
      }
      publish(*view);
    }
    update_capture_health();
    update_skew_health(node::monotonic_ns());
  }
}

void CameraServerNode::update_skew_health(int64_t now_ns) {
  if (skew_period_ns_ == 0) skew_period_ns_ = now_ns;
  if (now_ns - skew_period_ns_ < 1'000'000'000) return;
  skew_period_ns_ = now_ns;
  if (const auto s = skew_.take()) {
    runner_.health().set_counter("eye_skew_us_p50", s->p50_us);
    runner_.health().set_counter("eye_skew_us_max", s->max_us);
  }
}

void CameraServerNode::update_capture_health() {
  const CaptureHealth h = capture_->health();
  node::Health& health = runner_.health();
  const uint64_t drops = h.pairing.dropped_left + h.pairing.dropped_right;
  if (drops > reported_drops_) {
    health.drop(std::string(topics::kStereoFrame.spec.name), drops - reported_drops_);
    reported_drops_ = drops;
  }
  health.set_counter("frames_left", h.eyes[0].frames);
  health.set_counter("frames_right", h.eyes[1].frames);
  health.set_counter("unpaired_left", h.pairing.dropped_left);
  health.set_counter("unpaired_right", h.pairing.dropped_right);
  health.set_counter("corrupted_frames", h.eyes[0].corrupted + h.eyes[1].corrupted);
  health.set_counter("reopens", h.eyes[0].reopens + h.eyes[1].reopens);
  if (capture_->healthy()) {
    health.set_state(true, "streaming");
  } else {
    health.set_state(
        false, std::string(h.eyes[0].streaming ? "right" : "left") + " camera lost, reopening");
  }
}

// The rectified copy of a decoded view in storage, the view itself when not rectifying, or
// nullptr when it could not be rectified (counted in health; never published unrectified).
const stereo::FrameView* CameraServerNode::rectify(const stereo::FrameView& view,
                                                   stereo::FrameView& storage) {
  if (!params_.rectify || !rectifier_) return &view;
  const auto eyes = rectify_input(view);
  if (!eyes) {
    runner_.health().error("rectify", eyes.error());
    return nullptr;
  }
  if (auto e = rectifier_->rectify((*eyes)[0], (*eyes)[1], rectified_[0], rectified_[1]); !e) {
    runner_.health().error("rectify", e.error());
    return nullptr;
  }
  auto v = stereo::view_of_images(rectified_[0], rectified_[1], view.seq, view.stamp_ns);
  if (!v) {
    runner_.health().error("rectify", v.error());
    return nullptr;
  }
  storage = *v;
  storage.left.capture_stamp_ns = view.left.capture_stamp_ns;
  storage.right.capture_stamp_ns = view.right.capture_stamp_ns;
  storage.rectified = true;
  return &storage;
}

// The jpeg/png view in storage with frame_encoding set, else the view itself; nullptr when
// encoding failed (counted in health).
const stereo::FrameView* CameraServerNode::compress(const stereo::FrameView& view,
                                                    stereo::FrameView& storage) {
  if (!compressor_) return &view;
  const int64_t start_ns = node::monotonic_ns();
  auto v = compressor_->step(view);
  if (!v) {
    runner_.health().error("encode", v.error());
    return nullptr;
  }
  runner_.health().set_counter("encode_us",
                               static_cast<uint64_t>((node::monotonic_ns() - start_ns) / 1000));
  storage = *v;
  return &storage;
}

void CameraServerNode::check_eye_order(const stereo::FrameView& view) {
  if (!rectifier_) return;
  // Only the frames the watch samples are converted or decoded: a start-up check costs nothing
  // on the other frames, whatever the published encoding.
  cv::Mat left, right;
  if (eye_order_.due()) {
    auto l = eye_order_pixels(view.left, view.encoding, eye_order_pixels_[0]);
    auto r = eye_order_pixels(view.right, view.encoding, eye_order_pixels_[1]);
    if (!l || !r) {
      skip_eye_order(std::string(l ? "right" : "left") + " eye: " + (l ? r.error() : l.error()));
      return;
    }
    left = *l;
    right = *r;
  }
  const auto evidence = eye_order_.step(*rectifier_, left, right, false);
  if (!evidence) return;
  if (auto text = stereo::describe_swapped_eyes(*evidence, std::string(kHowToSwap))) {
    log::error(*text);
    runner_.health().error("eyes_swapped", *text);
  }
}

// A sampled frame whose eyes cannot be had uses up one of the watch's checks: a camera whose
// frames never decode reports each cause once and, when no check is left, that it gave up,
// instead of an error every 100th frame for ever.
void CameraServerNode::skip_eye_order(const std::string& why) {
  eye_order_.skip();
  if (eye_order_.given_up()) {
    const std::string text = "eye order not checked (check given up): " + why;
    log::warn(text);
    runner_.health().error("eye_order", text);
    return;
  }
  if (why == eye_order_skipped_) return;
  eye_order_skipped_ = why;
  runner_.health().error("eye_order", "eye order not checked: " + why);
}

// The view scaled to publish_width_px in storage, the view itself without a publish width, or
// nullptr when it could not be scaled (counted in health).
const stereo::FrameView* CameraServerNode::scale(const stereo::FrameView& view,
                                                 stereo::FrameView& storage) {
  if (!scaler_) return &view;
  auto v = scaler_->step(view);
  if (!v) {
    runner_.health().error("scale", v.error());
    return nullptr;
  }
  storage = *v;
  return &storage;
}

void CameraServerNode::publish(const stereo::FrameView& captured) {
  // Scaled first: the eye-order check, rectification and compression all work at the published
  // size with the published (scaled) calibration.
  stereo::FrameView scaled, rectified, compressed;
  const stereo::FrameView* in = scale(captured, scaled);
  if (in == nullptr) return;
  const stereo::FrameView& view = *in;
  const stereo::FrameView* out = nullptr;
  {
    std::lock_guard lock(calibration_mutex_);
    check_eye_order(view);
    out = rectify(view, rectified);
  }
  if (out != nullptr) out = compress(*out, compressed);
  if (out == nullptr) return;
  check_sample(*out);
  stereoball_msg_StereoFrame msg{};
  stereo::fill_frame_message(*out, source_name_, msg);
  frame_writer_.write(msg);
  runner_.health().count(std::string(topics::kStereoFrame.spec.name));
  offer_preview(*out);
}

void CameraServerNode::offer_preview(const stereo::FrameView& view) {
  // Compressed frames (frame_encoding, or a JPEG camera published natively) need no preview:
  // the viewer shows them as they are, so no preview writer is offered for it to wait on.
  if (compressor_ || params_.output.preview_max_width_px == 0) return;
  if (view.encoding != "bgr8" && view.encoding != "mono8" && view.encoding != "yuyv") return;
  if (!preview_)
    preview_ = std::make_unique<stereo::PreviewPublisher>(runner_.participant(), params_.output,
                                                          source_name_);
  preview_->offer(view);
  runner_.health().set_counter("preview_frames", preview_->published());
  runner_.health().set_counter("preview_encode_us", preview_->encode_us());
  if (auto error = preview_->take_error()) runner_.health().error("preview", *error);
}

}  // namespace stereoball::camera_server
