#include "ball_detector/node/ball_detector_node.hpp"

#include <string>

#include "ball_detector/node/detection_msg.hpp"
#include "common/dds/shared_memory.hpp"
#include "stereo/msg/calibration_msg.hpp"

namespace stereoball::ball_detector {
namespace {

const std::string kFrameTopic(topics::kStereoFrame.spec.name);
const std::string kCalibrationTopic(topics::kStereoCalibration.spec.name);
const std::string kDetectionTopic(topics::kBallDetection.spec.name);
// No frame for this long makes the node report itself unhealthy.
constexpr std::int64_t kInputTimeoutNs = 2'000'000'000;
// A frame handed over later than this after the previous callback ended was not waiting in the
// reader: the detector was idle, so frames missing before it never arrived.
constexpr std::int64_t kIdleNs = 2'000'000;

}  // namespace

BallDetectorNode::BallDetectorNode(node::Runner& runner, const BallDetectorParams& params,
                                   const std::string& frame_times_path, bool pin_threads)
    : runner_(runner),
      helper_(pin_threads),
      pipeline_(params),
      frames_(runner.participant(), topics::kStereoFrame),
      calibration_(runner.participant(), topics::kStereoCalibration),
      tracks_(runner.participant(), topics::kBallTrack),
      params_(params),
      detections_(runner.participant(), topics::kBallDetection) {
  pipeline_.set_task_runner(
      [this](int n, const std::function<void(int)>& task) { helper_.run(n, task); },
      TaskHelper::kThreads);
  if (!frame_times_path.empty()) {
    times_ = std::make_unique<FrameTimesLog>(frame_times_path);
    if (!times_->ok()) log::warn("cannot write frame times to ", frame_times_path);
    helper_.record_jobs(true);
    pipeline_.set_search_observer(
        [this](SearchPath path, bool started) { times_->search(path, started); });
  }
  // Every callback ends by noting when the node became free: a frame taken right after that
  // had been waiting (FrameGaps).
  runner_.on_data(calibration_.handle(), [this] {
    on_calibration();
    idle_since_ns_ = node::monotonic_ns();
  });
  runner_.on_data(frames_.handle(), [this] {
    on_frames();
    idle_since_ns_ = node::monotonic_ns();
  });
  runner_.every(1'000'000'000, [this](std::int64_t now_ns) {
    report_pinning();
    check_input(now_ns);
    report_gaps(now_ns);
    idle_since_ns_ = node::monotonic_ns();
  });
  runner_.health().set_state(false, "waiting for stereo/calibration");
}

void BallDetectorNode::report_pinning() {
  // Once, after the first frame pinned the frame thread (the helper pinned itself at start).
  if (pinning_reported_ || processed_ == 0) return;
  pinning_reported_ = true;
  const std::string problem = helper_.pin_problem();
  if (!problem.empty()) {
    log::warn("threads left to the scheduler: ", problem);
  } else if (const auto cpus = helper_.pinned_cpus()) {
    log::info("frame thread on CPU ", cpus->first, ", task helper on CPU ", cpus->second,
              " (--no-pin-threads leaves them to the scheduler)");
  }
}

void BallDetectorNode::on_calibration() {
  auto sample = calibration_.take_latest();
  if (!sample) return;
  runner_.health().count(kCalibrationTopic);
  const std::string source = (*sample)->source ? (*sample)->source : "";
  auto calib = stereo::calibration_from_message(**sample, params_.max_image_size());
  if (!calib) return reject_calibration(source, calib.error());
  const auto decision = gate_.offer(calib->image_size);
  if (!decision.use) {
    pending_calibration_ = CalibrationFrom{std::move(*calib), source};
    return reject_calibration(source, decision.reason);
  }
  apply_calibration(CalibrationFrom{std::move(*calib), source});
}

void BallDetectorNode::apply_calibration(const CalibrationFrom& calibration) {
  if (auto problem = pipeline_.set_calibration(calibration.calib); !problem)
    return reject_calibration(calibration.source, problem.error());
  gate_.applied(calibration.calib.image_size);
  pending_calibration_.reset();
  eye_order_.reset();
  // JPEG frames the pipeline shrinks by a whole factor are decoded at that size (a fraction of
  // a full decode, and no shrinking after it).
  decoder_.set_reduction(pipeline_.working_reduction());
  const cv::Size s = pipeline_.image_size();
  log::info("calibration from '", calibration.source, "': ", s.width, "x", s.height, " px, rms ",
            calibration.calib.rms_px, " px; rectification tables built");
  runner_.health().set_state(true, "detecting");
}

void BallDetectorNode::reject_calibration(const std::string& source, const std::string& problem) {
  runner_.health().error("bad_calibration",
                         "stereo/calibration from '" + source + "' rejected: " + problem);
  runner_.health().set_counter("bad_calibrations", ++bad_calibrations_);
  log::warn("stereo/calibration from '", source, "' rejected: ", problem,
            pipeline_.has_calibration() ? " (keeping the previous one)" : "");
}

void BallDetectorNode::check_frame_size(const stereoball_msg_StereoFrame& frame) {
  constexpr std::uint32_t kMaxSide = 1u << 30;  // keeps the cast to int exact
  const cv::Size size(static_cast<int>(std::min(frame.left.width_px, kMaxSide)),
                      static_cast<int>(std::min(frame.left.height_px, kMaxSide)));
  if (gate_.frame(size) && pending_calibration_) {
    log::info("frames are now ", size.width, "x", size.height,
              ": switching to the calibration held back");
    apply_calibration(*pending_calibration_);
  }
}

void BallDetectorNode::check_input(std::int64_t now_ns) {
  if (!pipeline_.has_calibration()) {
    runner_.health().set_state(false, "waiting for stereo/calibration");
  } else if (now_ns - last_frame_ns_ > kInputTimeoutNs) {
    runner_.health().set_state(false, "no stereo/frame for 2 s");
  } else {
    runner_.health().set_state(true, "detecting");
  }
}

void BallDetectorNode::on_frames() {
  auto loaned = frames_.take_loaned();
  const auto latest = loaned.latest_valid();
  if (!latest) return;
  std::uint64_t valid = 0;
  for (std::size_t i = 0; i < loaned.size(); ++i) valid += loaned.valid(i) ? 1 : 0;
  runner_.health().count(kFrameTopic, valid);
  last_frame_ns_ = node::now_ns();
  const stereoball_msg_StereoFrame& frame = loaned[*latest];
  if (times_) {
    helper_.take_jobs();  // jobs outside a frame's processing are not its own
    times_->arrived(frame.seq, frame.stamp_ns, loaned.info(*latest).source_timestamp,
                    helper_.helper_tid());
  }
  const std::int64_t arrived_ns = node::monotonic_ns();
  gaps_.step(frame.seq, idle_since_ns_ == 0 || arrived_ns - idle_since_ns_ > kIdleNs);
  count_skipped(frame.seq, valid - 1);
  check_transport(frame);
  check_frame_size(frame);
  process(frame);
}

// At the first frame (and whenever a frame is larger than any before): does such a sample fit
// the socket receive buffer? A frame that does not is reported once with the remedies.
void BallDetectorNode::check_transport(const stereoball_msg_StereoFrame& frame) {
  const std::uint64_t sample =
      stereo::frame_sample_bytes(frame.left.data._length, frame.right.data._length);
  if (sample <= largest_sample_bytes_) return;
  largest_sample_bytes_ = sample;
  if (!transport_) {
    transport_ = stereo::read_transport_limits(
        {dds::ensure_shared_memory_usable() == dds::SharedMemoryState::kOn,
         runner_.participant().built_in_config()});
    runner_.health().set_counter("receive_buffer_bytes", transport_->receive_buffer_bytes());
  }
  runner_.health().set_counter("frame_sample_bytes", sample);
  if (oversize_reported_) return;
  const std::string what = std::string(frame.encoding ? frame.encoding : "?") + " " +
                           std::to_string(frame.left.width_px) + "x" +
                           std::to_string(frame.left.height_px) + " frames received";
  if (auto warning = stereo::oversize_warning(sample, *transport_, what)) {
    oversize_reported_ = true;
    log::warn(*warning);
    runner_.health().error("frame_too_large", *warning);
  }
}

// Once a second: frames published but never received; a warning (at most once a minute) when
// they are frequent.
void BallDetectorNode::report_gaps(std::int64_t now_ns) {
  const FrameGapPeriod period = gaps_.take_period();
  runner_.health().set_counter("frames_lost_in_transport", gaps_.lost());
  runner_.health().set_counter("frames_replaced_while_busy", gaps_.replaced_while_busy());
  if (!frequent_losses(period) || !gap_log_.allow(now_ns)) return;
  char share[16];
  std::snprintf(share, sizeof share, "%.0f %%",
                100.0 * static_cast<double>(period.lost) /
                    static_cast<double>(period.received + period.lost));
  const std::uint64_t buffer = transport_ ? transport_->receive_buffer_bytes() : 0;
  log::warn("stereo/frame: ", period.lost, " of ", period.received + period.lost,
            " frames of the last second (", share,
            ") were published but never received (sequence gaps while the detector waited); "
            "largest sample ",
            largest_sample_bytes_, " bytes, socket receive buffer ", buffer, " bytes. ",
            stereo::transport_remedies(largest_sample_bytes_, transport_->keyless));
}

void BallDetectorNode::count_skipped(std::uint64_t seq, std::uint64_t batch_skipped) {
  // Keep-last-1 overwrites unread frames in the reader; the source's seq shows the gap.
  std::uint64_t skipped = batch_skipped;
  if (last_seq_ && seq > *last_seq_ + 1) skipped = std::max(skipped, seq - *last_seq_ - 1);
  if (skipped > 0) runner_.health().drop(kFrameTopic, skipped);
  last_seq_ = seq;
}

void BallDetectorNode::process(const stereoball_msg_StereoFrame& frame) {
  const std::int64_t start_ns = node::monotonic_ns();
  StereoDetection det;
  cv::Mat left;
  stereo::RowSource* right = nullptr;
  if (!pipeline_.has_calibration()) {
    det = pipeline_.step(cv::Mat(), cv::Mat(), false);  // kNoCalibration with its reason
  } else {
    // The eyes decoded at the same time on the helper's core (a 2304x1296 JPEG pair is a third
    // of the frame's CPU time); a JPEG right eye only as far as the helper gets meanwhile, the
    // rest as far as the search reads it.
    const auto both_cores = [this](int n, const std::function<void(int)>& task) {
      helper_.run(n, task);
    };
    if (auto st =
            decoder_.decode_right_lazily(frame, pipeline_.image_size(), left, right, both_cores);
        !st) {
      det.status = DetectionStatus::kBadFrame;
      det.reason = st.error();
    } else {
      if (times_) times_->decoded();
      // Both capture stamps known: their difference is the skew between the eyes' exposures.
      std::optional<std::int64_t> skew_ns;
      if (frame.left.capture_stamp_ns != 0 && frame.right.capture_stamp_ns != 0)
        skew_ns = frame.left.capture_stamp_ns - frame.right.capture_stamp_ns;
      det = pipeline_.step(left, *right, frame.rectified, prior_for(frame.stamp_ns), frame.stamp_ns,
                           skew_ns);
    }
  }
  ++processed_;
  if (det.status == DetectionStatus::kFound) ++found_;
  if (times_) times_->stepped();
  report_problem(det, frame.seq, node::now_ns());
  publish(det, frame, start_ns);
  if (times_) times_->published(static_cast<int>(det.status), det.search, helper_.take_jobs());
  // The answer is out: now the work that need not delay it. The eye-order check (tens of ms on
  // the frames it is due on) reads the frames as searched (the pipeline's rectifier is for its
  // working size), which finish_frame may overwrite: it goes first.
  if (left.empty()) return;
  if (det.status != DetectionStatus::kBadFrame) check_eye_order(left, *right, frame.rectified);
  pipeline_.finish_frame(left, frame.rectified);
}

void BallDetectorNode::check_eye_order(const cv::Mat& left, stereo::RowSource& right,
                                       bool rectified) {
  // The check reads the whole right eye: the rows the search left undecoded are decoded only
  // on the frames it is due on.
  if (eye_order_.due()) right.make_all();
  if (!right.status().ok()) return eye_order_.skip();
  const auto [searched_left, searched_right] = pipeline_.searched_frames(left, right.image());
  check_eye_order(*searched_left, *searched_right, rectified);
}

void BallDetectorNode::check_eye_order(const cv::Mat& left, const cv::Mat& right, bool rectified) {
  const auto evidence = eye_order_.step(*pipeline_.rectifier(), left, right, rectified);
  if (!evidence) return;
  if (auto text = stereo::describe_swapped_eyes(*evidence, kHowToSwapCameras)) {
    log::error(*text);
    runner_.health().error("eyes_swapped", *text);
  }
}

std::optional<PositionPrior> BallDetectorNode::prior_for(std::int64_t frame_stamp_ns) {
  if (auto sample = tracks_.take_latest()) last_track_ = from_message(**sample);
  if (!last_track_) return std::nullopt;
  return prior_from_track(*last_track_, frame_stamp_ns, params_.track_prior_gate_m,
                          params_.track_prior_max_age_ns);
}

void BallDetectorNode::report_problem(const StereoDetection& det, std::uint64_t seq,
                                      std::int64_t now_ns) {
  if (det.status == DetectionStatus::kBadFrame) {
    runner_.health().error("bad_frame", det.reason);
    runner_.health().set_counter("bad_frames", ++bad_frames_);
    if (bad_frame_log_.allow(now_ns)) {
      log::warn("bad frame ", seq, ": ", det.reason, " (", bad_frames_ - bad_frames_logged_ - 1,
                " more bad frames since the last report, ", bad_frames_, " in total)");
      bad_frames_logged_ = bad_frames_;
    }
  } else if (det.status == DetectionStatus::kNoCalibration) {
    runner_.health().set_counter("frames_without_calibration", ++uncalibrated_frames_);
    if (uncalibrated_log_.allow(now_ns)) {
      log::warn("frame ", seq, " not processed: no stereo/calibration yet (", uncalibrated_frames_,
                " frames so far)");
    }
  }
}

void BallDetectorNode::publish(const StereoDetection& det, const stereoball_msg_StereoFrame& frame,
                               std::int64_t start_mono_ns) {
  const float processing_ms = static_cast<float>(node::monotonic_ns() - start_mono_ns) * 1e-6f;
  stereoball_msg_BallDetection msg{};
  to_message(det, FrameStamp{frame.seq, frame.stamp_ns}, processing_ms, node::now_ns(), msg);
  detections_.write(msg);
  runner_.health().count(kDetectionTopic);
  runner_.health().set_counter("frames_processed", processed_);
  runner_.health().set_counter("balls_found", found_);
}

}  // namespace stereoball::ball_detector
