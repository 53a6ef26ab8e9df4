#include "live_station.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace stereoball::calibrate_live {
namespace {

std::string size_text(cv::Size s) {
  return std::to_string(s.width) + "x" + std::to_string(s.height);
}

std::string figures(const char* fmt, double a, double b = 0, double c = 0, double d = 0) {
  char text[200];
  std::snprintf(text, sizeof text, fmt, a, b, c, d);
  return text;
}

nlohmann::json points_json(const std::vector<cv::Point2f>& points) {
  auto out = nlohmann::json::array();
  for (const auto& p : points)
    out.push_back({std::round(p.x * 100) / 100, std::round(p.y * 100) / 100});
  return out;
}

nlohmann::json verdict_json(const Verdict& v) {
  const auto& c = v.result.calibration;
  nlohmann::json j;
  j["pass"] = v.pass;
  j["rms_px"] = c.rms_px;
  j["row_error_px"] = v.result.mean_rectified_row_error_px;
  j["max_row_error_px"] = v.result.max_rectified_row_error_px;
  j["baseline_m"] = std::abs(c.t[0]);
  j["focal_px"] = c.p1(0, 0);
  j["left_focal_px"] = c.k1(0, 0);
  j["right_focal_px"] = c.k2(0, 0);
  j["eyes_in_order"] = static_cast<bool>(stereo::check_camera_order(c));
  j["per_pose"] = nlohmann::json::array();
  for (const auto& e : v.per_pose)
    j["per_pose"].push_back({{"name", e.name}, {"rms_px", e.rms_px}});
  j["dropped"] = nlohmann::json::array();
  for (const auto& d : v.result.dropped)
    j["dropped"].push_back({{"name", d.name}, {"error_px", d.error_px}, {"reason", d.reason}});
  j["failures"] = v.failures;
  j["warnings"] = v.warnings;
  j["lines"] = verdict_lines(v);
  return j;
}

}  // namespace

std::vector<cv::Point2f> find_live_corners(const cv::Mat& eye,
                                           const stereo::BoardCalibrationParams& params) {
  if (eye.empty()) return {};
  cv::Mat grey;
  if (eye.channels() == 3)
    cv::cvtColor(eye, grey, cv::COLOR_BGR2GRAY);
  else
    grey = eye;
  const double scale = std::min(1.0, 800.0 / grey.cols);
  cv::Mat small = grey;
  if (scale < 1.0) cv::resize(grey, small, {}, scale, scale, cv::INTER_AREA);
  std::vector<cv::Point2f> corners;
  const int flags =
      cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE | cv::CALIB_CB_FAST_CHECK;
  if (!cv::findChessboardCorners(small, params.inner_corners, corners, flags)) return {};
  for (auto& c : corners) c *= static_cast<float>(1.0 / scale);
  const int half = params.subpix_window_px / 2;
  cv::cornerSubPix(grey, corners, cv::Size(half, half), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 50, 1e-3));
  return corners;
}

std::vector<std::string> verdict_lines(const Verdict& v) {
  const auto& c = v.result.calibration;
  std::vector<std::string> lines;
  for (const auto& e : v.per_pose) {
    char text[120];
    std::snprintf(text, sizeof text, "  %-10s %.3f px", e.name.c_str(), e.rms_px);
    lines.emplace_back(text);
  }
  for (const auto& d : v.result.dropped) lines.push_back("  dropped " + d.name + ": " + d.reason);
  lines.push_back(
      figures("stereo RMS %.3f px, mean rectified row error %.3f px (max %.3f px), baseline %.4f m",
              c.rms_px, v.result.mean_rectified_row_error_px, v.result.max_rectified_row_error_px,
              std::abs(c.t[0])) +
      figures(", focal %.1f px", c.p1(0, 0)));
  for (const auto& w : v.warnings) lines.push_back("warning: " + w);
  for (const auto& f : v.failures) lines.push_back("FAIL: " + f);
  lines.push_back(std::string("verdict: ") + (v.pass ? "PASS" : "FAIL"));
  return lines;
}

LiveStation::LiveStation(const StationParams& params) : params_(params) {}

StationStep LiveStation::add_frame(const StationFrame& frame, int64_t now_ns) {
  // Corners only for frames the session can use (no search on a refused frame).
  if (!fatal_.empty() || frame.rectified || (session_ && frame.left.size() != size_))
    return feed(frame, {}, {}, now_ns);
  return feed(frame, find_live_corners(frame.left, params_.live.board),
              find_live_corners(frame.right, params_.live.board), now_ns);
}

StationStep LiveStation::add_corners(const StationFrame& frame, std::vector<cv::Point2f> left_px,
                                     std::vector<cv::Point2f> right_px, int64_t now_ns) {
  return feed(frame, std::move(left_px), std::move(right_px), now_ns);
}

StationStep LiveStation::feed(const StationFrame& frame, std::vector<cv::Point2f> left_px,
                              std::vector<cv::Point2f> right_px, int64_t now_ns) {
  StationStep step;
  last_frame_ns_ = now_ns;
  stalled_ = false;
  seq_ = frame.seq;
  if (!fatal_.empty()) {
    step.refused = fatal_;
    return step;
  }
  if (frame.rectified) {
    fatal_ =
        "frames are rectified: calibration needs raw frames (set rectify: false in the "
        "camera_server config); nothing written";
    step.refused = fatal_;
    return step;
  }
  if (frame.left.empty() || frame.left.size() != frame.right.size()) {
    step.refused = "frame " + std::to_string(frame.seq) + ": the eyes differ in size";
    return step;
  }
  if (!session_) {
    size_ = frame.left.size();
    source_ = frame.source;
    session_.emplace(params_.live, size_);
  } else if (frame.left.size() != size_) {
    fatal_ = "the frame size changed from " + size_text(size_) + " to " +
             size_text(frame.left.size()) + " during calibration: nothing written";
    step.refused = fatal_;
    return step;
  }
  left_px_ = std::move(left_px);
  right_px_ = std::move(right_px);
  if (verdict_) return step;
  step.pose = session_->add_frame(frame.left_stamp_ns, left_px_, frame.right_stamp_ns, right_px_);
  if (session_->enough_poses()) {
    finish_now();
    step.verdict_ready = verdict_.has_value();
  }
  return step;
}

std::string LiveStation::check_stall(int64_t now_ns) {
  if (last_frame_ns_ < 0) last_frame_ns_ = now_ns;
  // Only while collecting: after the verdict (whose computation takes seconds on this thread)
  // or a failure, a pause of the frames changes nothing.
  if (stalled_ || verdict_ || !fatal_.empty() || now_ns - last_frame_ns_ < params_.stall_ns)
    return "";
  stalled_ = true;
  stall_text_ = figures(
      "no frames for %.1f s: is camera_server running on this domain and partition? "
      "(stereoball doctor)",
      (now_ns - last_frame_ns_) * 1e-9);
  return stall_text_;
}

void LiveStation::finish_now() {
  if (verdict_ || !fatal_.empty()) return;
  if (!session_) {
    fatal_ = "no stereo frame arrived: nothing written";
    return;
  }
  auto v = session_->finish();
  if (!v) {
    fatal_ = v.error() + "; nothing written";
    return;
  }
  verdict_ = std::move(v).value();
}

std::string LiveStation::message() const {
  if (!fatal_.empty()) return fatal_;
  if (stalled_) return stall_text_;
  if (verdict_)
    return verdict_->pass ? "verdict: PASS, the calibration may be written"
                          : "verdict: FAIL, nothing written: " + verdict_->failures.front();
  if (!session_) return "waiting for stereo/frame";
  return session_->progress().hint;
}

nlohmann::json LiveStation::state(int64_t now_ns) const {
  nlohmann::json j;
  j["type"] = "calibration";
  const auto& b = params_.live.board.inner_corners;
  j["board"] = std::to_string(b.width) + "x" + std::to_string(b.height);
  j["square_mm"] = params_.live.board.square_m * 1e3;
  j["phase"] = !fatal_.empty() ? "failed"
               : verdict_      ? "verdict"
               : session_      ? "collecting"
                               : "waiting";
  j["message"] = message();
  j["stalled"] = stalled_;
  j["frame_age_s"] = last_frame_ns_ < 0 ? -1.0 : (now_ns - last_frame_ns_) * 1e-9;
  j["image"] = {size_.width, size_.height};
  j["source"] = source_;
  j["seq"] = seq_;
  j["corners"] = {{"left", points_json(left_px_)}, {"right", points_json(right_px_)}};
  j["still_needed_s"] = params_.live.still.still_ns * 1e-9;
  j["poses"] = nlohmann::json::array();
  if (session_) {
    const Progress p = session_->progress();
    j["progress"] = {{"poses", p.poses},
                     {"target", p.target_poses},
                     {"min_poses", params_.live.board.min_pairs},
                     {"x", p.coverage[0]},
                     {"y", p.coverage[1]},
                     {"size", p.coverage[2]},
                     {"skew", p.coverage[3]},
                     {"depth", p.depth_coverage},
                     {"still_left_s", p.left.still_ns * 1e-9},
                     {"still_right_s", p.right.still_ns * 1e-9},
                     {"board_left", p.left.board_seen},
                     {"board_right", p.right.board_seen},
                     {"frames", p.frames},
                     {"skipped_repeats", p.skipped_duplicates},
                     {"hint", p.hint}};
    for (const auto& r : session_->records())
      j["poses"].push_back({{"index", r.index},
                            {"x", r.view.x},
                            {"y", r.view.y},
                            {"size", r.view.size},
                            {"skew", r.view.skew},
                            {"disparity_px", r.disparity_px}});
  }
  j["verdict"] = verdict_ ? verdict_json(*verdict_) : nlohmann::json();
  j["written"] = written_;
  j["write_error"] = write_error_;
  return j;
}

Result<Verdict> LiveStation::writable_verdict() const {
  if (!fatal_.empty()) return Error{fatal_};
  if (!verdict_)
    return Error{"no verdict yet: " + std::to_string(session_ ? session_->records().size() : 0) +
                 " of " + std::to_string(params_.live.target_poses) +
                 " poses taken; nothing written"};
  if (!verdict_->pass)
    return Error{"the verdict failed (" + verdict_->failures.front() + "); nothing written"};
  return *verdict_;
}

void LiveStation::note_written(const std::string& path) {
  written_ = path;
  write_error_.clear();
}

void LiveStation::note_write_error(const std::string& error) {
  write_error_ = error;
}

}  // namespace stereoball::calibrate_live
