#include "calibration_pump.hpp"

#include "common/dds/reader.hpp"
#include "common/dds/waitset.hpp"
#include "common/node/node_runner.hpp"
#include "common/util/log.hpp"
#include "live_frames.hpp"
#include "live_output.hpp"
#include "stereoball/topics.hpp"

namespace stereoball::view {

CalibrationPump::CalibrationPump(const dds::DomainParticipant& participant,
                                 const calibrate_live::StationParams& params, std::string output,
                                 int64_t timeout_ns)
    : participant_(participant),
      output_(std::move(output)),
      timeout_ns_(timeout_ns),
      station_(params) {}

CalibrationPump::~CalibrationPump() {
  stop();
}

void CalibrationPump::start() {
  thread_ = std::thread([this] { run(); });
}

void CalibrationPump::stop() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

std::string CalibrationPump::state_json() {
  std::lock_guard lock(mutex_);
  auto j = station_.state(node::monotonic_ns());
  j["output"] = output_;
  return j.dump();
}

void CalibrationPump::finish() {
  std::lock_guard lock(mutex_);
  log::info("calibration: finish asked from the page");
  station_.finish_now();
  log_changes();
}

Status CalibrationPump::write() {
  std::lock_guard lock(mutex_);
  auto verdict = station_.writable_verdict();
  Status st = verdict ? calibrate_live::write_live_calibration(
                            output_, station_.params().live, *verdict,
                            "written by the calibration page of stereoball view")
                      : Status(Error{verdict.error()});
  if (!st) {
    station_.note_write_error(st.error());
    log::warn("calibration: ", st.error());
    return st;
  }
  station_.note_written(output_);
  log::info("calibration: wrote ", output_,
            "; camera_server publishes it within a second when its calibration_file names it");
  return {};
}

void CalibrationPump::log_changes() {
  const std::string message = station_.message();
  if (message != last_message_) {
    if (station_.fatal().empty() && !station_.stalled())
      log::info("calibration: ", message);
    else
      log::warn("calibration: ", message);
    last_message_ = message;
  }
  if (station_.verdict() && !verdict_logged_) {
    verdict_logged_ = true;
    for (const auto& line : calibrate_live::verdict_lines(*station_.verdict()))
      log::info("calibration: ", line);
  }
}

void CalibrationPump::run() {
  dds::DataReader<stereoball_msg_StereoFrame> frames(participant_, topics::kStereoFrame);
  dds::ReadCondition readable(frames.handle());
  dds::WaitSet waitset(participant_);
  waitset.attach(readable.handle(), 0);
  stereo::FrameDecoder decoder;
  const int64_t start_ns = node::monotonic_ns();
  bool timed_out = false;
  while (!stop_) {
    waitset.wait(100'000'000);
    if (finish_requested_.exchange(false)) finish();
    if (write_requested_.exchange(false)) (void)write();
    const int64_t now = node::monotonic_ns();
    {
      std::lock_guard lock(mutex_);
      station_.check_stall(now);
      if (!timed_out && now - start_ns > timeout_ns_) {
        timed_out = true;
        log::warn("calibration: time is up (--timeout-s): judging the poses taken");
        station_.finish_now();
      }
      log_changes();
    }
    auto sample = frames.take_latest();
    if (!sample) continue;
    auto frame = calibrate_live::station_frame(**sample, decoder);
    if (!frame) {
      log::warn("calibration: ", frame.error());
      continue;
    }
    // Corners are searched outside the lock: the page's polls never wait for OpenCV.
    std::vector<cv::Point2f> left_px, right_px;
    bool search = false;
    {
      std::lock_guard lock(mutex_);
      search = station_.fatal().empty() && !frame->rectified;
    }
    if (search) {
      left_px = calibrate_live::find_live_corners(frame->left, station_.params().live.board);
      right_px = calibrate_live::find_live_corners(frame->right, station_.params().live.board);
    }
    std::lock_guard lock(mutex_);
    const auto step =
        station_.add_corners(*frame, std::move(left_px), std::move(right_px), node::monotonic_ns());
    if (step.pose)
      log::info("calibration: pose ", step.pose->index, " taken: x ", step.pose->view.x, " y ",
                step.pose->view.y, " size ", step.pose->view.size, " skew ", step.pose->view.skew,
                ", board disparity ", step.pose->disparity_px, " px");
    log_changes();
  }
}

}  // namespace stereoball::view
