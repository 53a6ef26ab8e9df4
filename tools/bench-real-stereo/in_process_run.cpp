// run_in_process and the ball/detection conversions both paths share.

#include <algorithm>
#include <chrono>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <set>

#include "ball_detector/core/circle.hpp"
#include "ball_detector/node/detection_msg.hpp"
#include "ball_detector/pipeline/detector_params.hpp"
#include "ball_detector/pipeline/stereo_pipeline.hpp"
#include "camera_server/core/frame_scaler.hpp"
#include "common/util/bench_clock.hpp"
#include "real_stereo_run.hpp"
#include "stereo/core/calibration_scaling.hpp"

#include "common/msg/msg_names.hpp"
#include "stereo/frame/frame_compressor.hpp"
#include "stereo/frame/frame_decoder.hpp"
#include "stereo/frame/frame_msg.hpp"
#include "stereo/io/calibration_file.hpp"
#include "stereo/msg/calibration_msg.hpp"

namespace stereoball::real_stereo {
namespace {

// An image as camera_server's file source reads it (file_encoding as_read).
Result<cv::Mat> read_as_camera_server(const std::string& path) {
  cv::Mat m = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (m.empty()) return Error{path + ": cannot read or decode the image"};
  if (m.depth() != CV_8U) return Error{path + ": only 8-bit images are supported"};
  if (m.channels() == 4) cv::cvtColor(m, m, cv::COLOR_BGRA2BGR);
  if (m.channels() != 1 && m.channels() != 3)
    return Error{path + ": unsupported channel count " + std::to_string(m.channels())};
  if (!m.isContinuous()) m = m.clone();
  return m;
}

// Each search's own thread CPU time (a search running inside another is charged to itself),
// and the frames that ran it.
class SearchTimer {
 public:
  void on(ball_detector::SearchPath path, bool started) {
    const double now = bench::thread_cpu_ms();
    if (!open_.empty()) entry(open_.back()).total_ms += now - since_;
    since_ = now;
    if (started) {
      SearchCpu& e = entry(ball_detector::to_string(path));
      if (ran_.insert(e.path).second) ++e.frames;
      open_.push_back(e.path);
    } else if (!open_.empty()) {
      open_.pop_back();
    }
  }
  void start_frame() { ran_.clear(); }
  // The frame's time outside every search: decoding the eyes, and the rest (the answer's
  // checks, the patch, shrinking frames to the working width).
  void end_frame(double frame_cpu_ms, double searches_before_ms, double decode_ms) {
    const double searches = searches_ms() - searches_before_ms;
    SearchCpu& decode = entry("decode");
    decode.total_ms += decode_ms;
    ++decode.frames;
    SearchCpu& other = entry("other");
    other.total_ms += frame_cpu_ms - searches - decode_ms;
    ++other.frames;
  }
  double searches_ms() const {
    double sum = 0.0;
    for (const SearchCpu& e : totals_)
      if (e.path != "other" && e.path != "decode") sum += e.total_ms;
    return sum;
  }
  const std::vector<SearchCpu>& totals() const { return totals_; }

 private:
  SearchCpu& entry(const std::string& path) {
    for (SearchCpu& e : totals_)
      if (e.path == path) return e;
    totals_.push_back(SearchCpu{path, 0.0, 0});
    return totals_.back();
  }
  std::vector<SearchCpu> totals_;
  std::vector<std::string> open_;
  std::set<std::string> ran_;
  double since_ = 0.0;
};

// A circle detector beside the pipeline on the same decoded left eye: shrunk and rectified as
// the pipeline searches it (not timed), then the method alone (timed): what one eye costs with
// it.
class ReferenceEye {
 public:
  static Result<ReferenceEye> create(const std::string& method, const DetectorConfig& config,
                                     const ball_detector::StereoPipeline& pipeline) {
    ReferenceEye eye;
    // The node's radius range and separation, at the working width as its detector scales them.
    const ball_detector::PixelToPixelParams p2p = ball_detector::scaled_to_width(
        config.params.p2p, config.params.p2p_reference_width_px, pipeline.working_size().width);
    ball_detector::DetectorOptions o;
    o.min_radius_px = p2p.min_radius_px;
    o.max_radius_px = p2p.max_radius_px;
    o.min_separation_px = p2p.min_separation_px;
    o.max_circles = config.params.max_candidates_per_eye;
    std::string error;
    eye.detector_ = ball_detector::make_detector(method, o, &error);
    if (!eye.detector_) return Error{"reference: " + error};
    return eye;
  }

  // Call after pipeline.step(left, right, ...) and before its finish_frame.
  ReferenceFrame run(const ball_detector::StereoPipeline& pipeline, const cv::Mat& left,
                     bool rectified, double decode_cpu_ms) {
    ReferenceFrame f;
    f.decode_cpu_ms = decode_cpu_ms;
    const cv::Mat& searched = *pipeline.searched_frames(left, left).first;
    if (!rectified && !pipeline.rectifier()->rectify_eye(stereo::Eye::kLeft, searched, rectified_))
      return f;
    const cv::Mat& eye = rectified ? searched : rectified_;
    const double start = bench::thread_cpu_ms();
    const std::vector<ball_detector::Circle> circles = detector_->detect(eye);
    f.detect_cpu_ms = bench::thread_cpu_ms() - start;
    // Working pixels to the played frame's (the pipeline's to_input_pixels).
    const double s = double(pipeline.image_size().width) / double(pipeline.working_size().width);
    for (const auto& c : circles)
      f.circles.push_back({(c.x_px + 0.5) * s - 0.5, (c.y_px + 0.5) * s - 0.5, c.radius_px * s});
    return f;
  }

 private:
  std::unique_ptr<ball_detector::CircleDetector> detector_;
  cv::Mat rectified_;
};

}  // namespace

Status check_reference_method(const std::string& method) {
  const auto names = ball_detector::detector_names();
  if (std::find(names.begin(), names.end(), method) != names.end()) return {};
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
  return Error{"unknown reference method '" + method + "' (one of: " + list + ")"};
}

std::string status_name(stereoball_msg_DetectionStatus status) {
  return msg::lower_or_number(msg::detection_status_name(status), status);
}

bool is_refusal(stereoball_msg_DetectionStatus status) {
  return status == stereoball_msg_DETECTION_NO_CALIBRATION ||
         status == stereoball_msg_DETECTION_BAD_FRAME;
}

Detection detection_from_message(const stereoball_msg_BallDetection& msg) {
  Detection d;
  d.found = msg.status == stereoball_msg_DETECTION_FOUND;
  d.status = status_name(msg.status);
  d.reason = msg.reason ? msg.reason : "";
  d.left_x_px = msg.left.x_px;
  d.left_y_px = msg.left.y_px;
  d.left_r_px = msg.left.radius_px;
  d.z_m = msg.position_m[2];
  d.processing_ms = msg.processing_ms;
  return d;
}

RunResult run_in_process(const RealStereoSet& set, const DetectorConfig& config,
                         const RunOptions& options) {
  RunResult out;
  out.mode = "in-process";
  out.pairs.resize(set.truth.size());
  auto fail_all = [&](const std::string& error) {
    out.errors.push_back(error);
    return out;
  };
  // The calibration travels as its message and is read back with the node's image limit.
  auto file_calib = stereo::load_calibration(set.calibration_path);
  if (!file_calib) return fail_all(set.calibration_path + ": " + file_calib.error());
  // --width-px: camera_server's publish_width_px (its scaler, the calibration scaled with it).
  std::optional<camera_server::FrameScaler> scaler;
  if (options.width_px != 0) {
    scaler.emplace(options.width_px);
    out.scale = double(options.width_px) / double(set.image_size.width);
    auto scaled =
        stereo::scale_calibration(*file_calib, scaler->output_size(file_calib->image_size));
    if (!scaled) return fail_all(set.calibration_path + ": " + scaled.error());
    file_calib = std::move(scaled);
  }
  const auto msg = stereo::calibration_to_message(*file_calib, 0, set.calibration_path);
  auto calib = stereo::calibration_from_message(msg, config.params.max_image_size());
  if (!calib)
    return fail_all("ball_detector would refuse the calibration: " + calib.error() +
                    " (raise the detector's image_limit: --image-limit WxH)");
  // One OpenCV thread: the thread's CPU time is then the detector's whole cost on one core.
  cv::setNumThreads(1);
  ball_detector::StereoPipeline pipeline(config.params);
  SearchTimer timer;
  pipeline.set_search_observer(
      [&timer](ball_detector::SearchPath path, bool started) { timer.on(path, started); });
  if (auto st = pipeline.set_calibration(*calib); !st)
    return fail_all("ball_detector would refuse the calibration: " + st.error());
  out.played_size = pipeline.image_size();
  stereo::FrameCodecParams codec;
  codec.frame_encoding = options.frame_encoding;
  codec.jpeg_quality = options.jpeg_quality;
  codec.jpeg_chroma = options.jpeg_chroma;
  std::optional<stereo::FrameCompressor> compressor;
  if (codec.compressed()) compressor.emplace(codec);
  stereo::FrameDecoder decoder;
  const auto run_in_turn = [](int n, const std::function<void(int)>& task) {
    for (int t = 0; t < n; ++t) task(t);
  };
  decoder.set_reduction(pipeline.working_reduction());  // as the node decodes
  std::optional<ReferenceEye> reference;
  if (!options.reference.empty()) {
    auto made = ReferenceEye::create(options.reference, config, pipeline);
    if (!made) return fail_all(made.error());
    reference.emplace(std::move(*made));
    out.reference.resize(set.truth.size());
  }
  for (std::size_t i = 0; i < set.truth.size(); ++i) {
    if (options.stop && options.stop->load()) return fail_all("interrupted");
    const TruthRow& row = set.truth[i];
    auto left = read_as_camera_server(set.left_path(row));
    auto right = read_as_camera_server(set.right_path(row));
    if (!left || !right) {
      out.errors.push_back("pair " + row.pair + ": " + (!left ? left.error() : right.error()));
      continue;
    }
    const std::int64_t stamp_ns = static_cast<std::int64_t>(i) * 1'000'000'000;
    auto view = stereo::view_of_images(*left, *right, i, stamp_ns);
    if (!view) {
      out.errors.push_back("pair " + row.pair + ": " + view.error());
      continue;
    }
    stereo::FrameView sent = *view;
    if (scaler) {
      auto scaled = scaler->step(*view);
      if (!scaled) return fail_all("pair " + row.pair + ": " + scaled.error());
      sent = *scaled;
    }
    if (compressor) {
      auto c = compressor->step(sent);
      if (!c) {
        out.errors.push_back("pair " + row.pair + ": " + c.error());
        continue;
      }
      sent = *c;
    }
    stereoball_msg_StereoFrame frame{};
    stereo::fill_frame_message(sent, "files", frame);
    // Timed as the node times it: decoding, the pipeline's step (finish_frame comes after the
    // answer and is not in processing_ms).
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = bench::thread_cpu_ms();
    timer.start_frame();
    const double searches_before_ms = timer.searches_ms();
    ball_detector::StereoDetection det;
    cv::Mat l;
    stereo::RowSource* r = nullptr;
    // One core, as the node decodes on one: the left eye whole, the right one as far as the
    // searches read it (its decoding is then part of theirs).
    const Status decoded =
        decoder.decode_right_lazily(frame, pipeline.image_size(), l, r, run_in_turn);
    const double decode_ms = bench::thread_cpu_ms() - cpu_start;
    if (!decoded) {
      det.status = ball_detector::DetectionStatus::kBadFrame;
      det.reason = decoded.error();
    } else {
      det = pipeline.step(l, *r, frame.rectified, std::nullopt, stamp_ns);
    }
    const float ms =
        std::chrono::duration<float, std::milli>(std::chrono::steady_clock::now() - start).count();
    const double cpu_ms = bench::thread_cpu_ms() - cpu_start;
    timer.end_frame(cpu_ms, searches_before_ms, decode_ms);
    stereoball_msg_BallDetection msg_out{};
    ball_detector::to_message(det, ball_detector::FrameStamp{i, stamp_ns}, ms, stamp_ns, msg_out);
    if (is_refusal(msg_out.status)) {
      out.errors.push_back("pair " + row.pair + ": the detector refused the frame (" +
                           status_name(msg_out.status) + ": " + det.reason + ")");
      continue;
    }
    out.pairs[i].detection = detection_from_message(msg_out);
    out.pairs[i].detection->cpu_ms = cpu_ms;
    out.pairs[i].attempts = 1;
    if (reference && decoded)
      out.reference[i] = reference->run(pipeline, l, frame.rectified, decode_ms);
    if (!l.empty()) pipeline.finish_frame(l, frame.rectified);
  }
  out.cpu_by_search = timer.totals();
  return out;
}

}  // namespace stereoball::real_stereo
