#include "stereo/core/still_board.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace stereoball::stereo {

Status StillBoardParams::validate() const {
  if (!std::isfinite(max_motion_px) || max_motion_px <= 0.0 || max_motion_px > 100.0) {
    return Error{"max_motion_px: must be in (0, 100] pixels, got " + std::to_string(max_motion_px)};
  }
  if (still_ns < 0 || still_ns > 60'000'000'000) {
    return Error{"still_ns: must be in [0, 60 s], got " + std::to_string(still_ns)};
  }
  if (max_gap_ns <= 0 || max_gap_ns > 60'000'000'000) {
    return Error{"max_gap_ns: must be in (0, 60 s], got " + std::to_string(max_gap_ns)};
  }
  return {};
}

double max_corner_motion_px(const std::vector<cv::Point2f>& a, const std::vector<cv::Point2f>& b) {
  if (a.size() != b.size()) return std::numeric_limits<double>::infinity();
  double worst = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    worst = std::max(worst, std::hypot(static_cast<double>(a[i].x - b[i].x),
                                       static_cast<double>(a[i].y - b[i].y)));
  }
  return worst;
}

StillBoardSelector::StillBoardSelector(const StillBoardParams& params) : params_(params) {}

void StillBoardSelector::reset() {
  runs_[0] = Run{};
  runs_[1] = Run{};
}

EyeStillness StillBoardSelector::stillness(Eye eye) const {
  const Run& r = runs_[static_cast<int>(eye)];
  if (!r.active) return {};
  return {true, r.last_ns - r.start_ns};
}

std::optional<StillPose> StillBoardSelector::add(Eye eye, int64_t stamp_ns,
                                                 const std::vector<cv::Point2f>& corners) {
  Run& run = runs_[static_cast<int>(eye)];
  if (corners.empty()) {
    run = Run{};
    return std::nullopt;
  }
  const bool continues = run.active && stamp_ns >= run.last_ns &&
                         stamp_ns - run.last_ns <= params_.max_gap_ns &&
                         max_corner_motion_px(run.anchor, corners) <= params_.max_motion_px;
  if (continues) {
    run.last_ns = stamp_ns;
    run.last = corners;
  } else {
    run = Run{true, false, stamp_ns, stamp_ns, corners, corners};
  }
  Run& l = runs_[0];
  Run& r = runs_[1];
  if (!l.active || !r.active || l.taken || r.taken) return std::nullopt;
  // Each eye was still over [start, last] on its own clock; the board stood still in both
  // only in the overlap, which is what free-running eyes make shorter.
  const int64_t from = std::max(l.start_ns, r.start_ns);
  const int64_t to = std::min(l.last_ns, r.last_ns);
  if (to - from < params_.still_ns) return std::nullopt;
  l.taken = r.taken = true;
  return StillPose{l.last, r.last, l.last_ns, r.last_ns, from};
}

}  // namespace stereoball::stereo
