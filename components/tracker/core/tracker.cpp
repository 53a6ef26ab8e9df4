#include "tracker/core/tracker.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "tracker/core/statistical_verifier.hpp"

namespace stereoball::tracker {
namespace {

std::string ssd_text(std::optional<std::int64_t> ssd, const BlockMatcher& m, bool patch_valid) {
  char buf[96];
  if (!patch_valid) return "block match: no patch";
  if (!ssd) return "block match: no reference";
  std::snprintf(buf, sizeof buf, "block match: ssd %lld %s %.0f", static_cast<long long>(*ssd),
                m.is_match(*ssd) ? "<" : ">=", m.threshold());
  return buf;
}

}  // namespace

Tracker::Tracker(const TrackerParams& params)
    : params_(params), matcher_(params.ssd_threshold), register_(params.register_size) {}

void Tracker::reset() {
  *this = Tracker(params_);
}

Track Tracker::step(const Detection& detection, std::int64_t now_ns) {
  note_input(now_ns);
  // Positions older than this say nothing about the present (the camera moves).
  const auto& entries = register_.entries();
  if (!entries.empty() && now_ns - entries.back().stamp_ns > params_.register_max_age_ns) {
    register_.clear();
  }
  Decision decision;
  if (!detection.found) {
    decision = {Verdict::kNoDetection, "detector found no ball", -1.0};
  } else if (!in_range(detection.position_m)) {
    decision = {Verdict::kRejected, out_of_range_text(detection.position_m), -1.0};
  } else if (state_ == TrackState::kIdle) {
    decision = decide_startup(detection, now_ns);
  } else {
    decision = decide_tracking(detection, now_ns);
  }
  if (is_accepted(decision.verdict)) {
    accept(detection, now_ns);
  } else {
    miss(now_ns);
  }
  return make_track(decision);
}

bool Tracker::in_range(const Eigen::Vector3d& position_m) const {
  return position_m.allFinite() && position_m.norm() <= params_.max_range_m;
}

std::string Tracker::out_of_range_text(const Eigen::Vector3d& position_m) const {
  char buf[128];
  std::snprintf(buf, sizeof buf, "position %.3g m from the camera is beyond max_range_m %.3g m",
                position_m.norm(), params_.max_range_m);
  return buf;
}

Tracker::Decision Tracker::decide_startup(const Detection& d, std::int64_t now_ns) {
  // Paper: no block matching yet; the sixth position must fit the first five.
  if (!register_.full()) {
    register_.push(d.position_m, now_ns);
    char buf[64];
    std::snprintf(buf, sizeof buf, "collecting positions %d/%d", register_.size(),
                  params_.register_size);
    return {Verdict::kStartupCollecting, buf, -1.0};
  }
  const StatsCheck check = check_position(register_, d.position_m, now_ns, params_);
  register_.push(d.position_m, now_ns);
  if (check.accepted) return {Verdict::kStartupAccepted, check.reason, -1.0};
  return {Verdict::kStartupInconsistent, check.reason, -1.0};
}

Tracker::Decision Tracker::decide_tracking(const Detection& d, std::int64_t now_ns) {
  Decision out;
  const auto ssd = d.patch_valid ? matcher_.ssd(d.patch_rgb) : std::nullopt;
  if (ssd) out.ssd = static_cast<double>(*ssd);
  const std::string block = ssd_text(ssd, matcher_, d.patch_valid);
  // A gross jump is not the ball however similar the block looks.
  const bool jump_ok =
      (d.position_m - last_position_m_).norm() <= max_jump_m(params_, now_ns - last_accepted_ns_);
  const StatsCheck check =
      check_position(register_, d.position_m, now_ns, params_, params_.register_outliers_allowed,
                     params_.reacquire_positions);
  // Paper: whatever the result, the position is shifted into the register.
  register_.push(d.position_m, now_ns);
  if (ssd && matcher_.is_match(*ssd) && jump_ok) {
    out.verdict = Verdict::kBlockMatchAccepted;
    out.reason = block;
  } else if (check.accepted && jump_ok) {
    // The jump gate holds here too: when detections alternate between the ball and a
    // look-alike elsewhere, the register mixes both and its spread would accept either. The
    // gate widens with the time since the last acceptance, so reacquisition after a loss works.
    out.verdict = Verdict::kStatisticsAccepted;
    out.reason = block + (jump_ok ? "; " : " but jump too large; ") + check.reason;
  } else {
    out.verdict = Verdict::kRejected;
    out.reason = block + (jump_ok ? "; " : " but jump too large; ") + check.reason;
  }
  return out;
}

void Tracker::accept(const Detection& d, std::int64_t now_ns) {
  // The reference is refreshed on every accepted block, also after a
  // statistics acceptance: otherwise a ball reacquired under new lighting or
  // size would never block-match again.
  if (d.patch_valid) matcher_.store(d.patch_rgb);
  has_accepted_ = true;
  last_position_m_ = d.position_m;
  last_accepted_ns_ = now_ns;
  frames_since_accept_ = 0;
  state_ = TrackState::kFollowing;
  update_velocity(now_ns);
  side_ = side_of(d);
}

void Tracker::note_input(std::int64_t now_ns) {
  if (has_input_ && now_ns - last_input_ns_ > params_.lost_after_ns) {
    // Nothing arrived for longer than a loss takes: judge the ball on what arrives from now on
    // (the register's age rule already drops the old positions).
    loss_clock_from_ns_ = now_ns;
    frames_since_accept_ = 0;
  }
  has_input_ = true;
  last_input_ns_ = now_ns;
}

void Tracker::miss(std::int64_t now_ns) {
  ++frames_since_accept_;
  if (state_ != TrackState::kFollowing) return;
  const std::int64_t without_acceptance_ns =
      now_ns - std::max(last_accepted_ns_, loss_clock_from_ns_);
  if (frames_since_accept_ >= params_.lost_after_frames ||
      without_acceptance_ns >= params_.lost_after_ns) {
    state_ = TrackState::kSearching;
  }
}

void Tracker::update_velocity(std::int64_t now_ns) {
  while (!accepted_.empty() && now_ns - accepted_.front().stamp_ns > params_.velocity_window_ns) {
    accepted_.pop_front();
  }
  accepted_.push_back({last_position_m_, now_ns});
  // Least-squares slope of position over time: the best-fit line's speed.
  const double n = static_cast<double>(accepted_.size());
  double t_mean = 0.0;
  Eigen::Vector3d p_mean = Eigen::Vector3d::Zero();
  for (const auto& a : accepted_) {
    t_mean += static_cast<double>(a.stamp_ns - now_ns) * 1e-9;
    p_mean += a.position_m;
  }
  t_mean /= n;
  p_mean /= n;
  double stt = 0.0;
  Eigen::Vector3d stp = Eigen::Vector3d::Zero();
  for (const auto& a : accepted_) {
    const double dt = static_cast<double>(a.stamp_ns - now_ns) * 1e-9 - t_mean;
    stt += dt * dt;
    stp += dt * (a.position_m - p_mean);
  }
  velocity_mps_ = stt > 1e-9 ? Eigen::Vector3d(stp / stt) : Eigen::Vector3d::Zero();
}

Side Tracker::side_of(const Detection& d) const {
  // Offset from the image centre in [-1, 1], positive to the right.
  double offset = d.position_m.x() > 0.0 ? 1.0 : (d.position_m.x() < 0.0 ? -1.0 : 0.0);
  if (d.image_width_px > 0) {
    const double half = 0.5 * static_cast<double>(d.image_width_px);
    offset = (d.left_x_px - half) / half;
  }
  // Near the centre the column says little; the lateral motion says where it went.
  const double vx = velocity_mps_.x();
  if (std::abs(offset) < params_.side_center_band_fraction &&
      std::abs(vx) >= params_.side_min_speed_mps) {
    return vx > 0.0 ? Side::kRight : Side::kLeft;
  }
  if (offset > 0.0) return Side::kRight;
  if (offset < 0.0) return Side::kLeft;
  return side_;
}

Track Tracker::make_track(const Decision& decision) const {
  Track t;
  t.state = state_;
  t.verdict = decision.verdict;
  t.reason = decision.reason;
  t.ssd = decision.ssd;
  t.position_valid = has_accepted_ && state_ != TrackState::kIdle;
  t.last_seen_side = side_;
  t.last_accepted_stamp_ns = last_accepted_ns_;
  if (has_accepted_) {
    t.position_m = last_position_m_;
    t.velocity_mps = velocity_mps_;
    t.bearing_rad = std::atan2(last_position_m_.x(), last_position_m_.z());
    t.distance_m = std::hypot(last_position_m_.x(), last_position_m_.z());
  }
  return t;
}

}  // namespace stereoball::tracker
