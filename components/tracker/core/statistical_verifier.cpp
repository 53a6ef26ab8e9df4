#include "tracker/core/statistical_verifier.hpp"

#include <algorithm>
#include <cstdio>
#include <vector>

namespace stereoball::tracker {
namespace {

bool steps_plausible(std::span<const StampedPosition> e, const TrackerParams& params) {
  for (std::size_t i = 1; i < e.size(); ++i) {
    const double step = (e[i].position_m - e[i - 1].position_m).norm();
    if (step > max_jump_m(params, e[i].stamp_ns - e[i - 1].stamp_ns)) return false;
  }
  return true;
}

bool register_consistent(const StatsCheck& c) {
  return c.register_full && c.steps_plausible && (c.static_cluster || c.clean_line);
}

// A line of positions with one stray detection in it can still pass as clean (its RMS spreads
// the stray's offset over every position), yet the stray tilts the line enough to reject the
// next ball position: a position farther than the tolerance from the line of the others marks
// it (the others' line: a stray at an end pulls the line of all through itself).
bool holds_stray(std::span<const StampedPosition> points, const TrackerParams& params) {
  std::vector<StampedPosition> others;
  for (std::size_t i = 0; i < points.size(); ++i) {
    others.clear();
    for (std::size_t j = 0; j < points.size(); ++j)
      if (j != i) others.push_back(points[j]);
    const auto stats = compute_stats(others);
    if (stats && distance_to_line(points[i].position_m, stats->mean_m, stats->line_direction) >
                     params.line_tolerance_m)
      return true;
  }
  return false;
}

std::string describe(const StatsCheck& c, int size, int capacity) {
  char buf[256];
  if (!c.register_full) {
    std::snprintf(buf, sizeof buf, "statistics: register %d/%d", size, capacity);
  } else if (!register_consistent(c)) {
    std::snprintf(buf, sizeof buf,
                  "statistics: register inconsistent (spread %.3f m, line rms %.3f m%s)", c.sigma_m,
                  c.line_rms_m, c.steps_plausible ? "" : ", implausible steps");
  } else if (!c.jump_plausible) {
    std::snprintf(buf, sizeof buf, "statistics: jump too large");
  } else {
    std::snprintf(buf, sizeof buf,
                  "statistics: |p-mean| %.3f m %s %.3f m, line distance %.3f m %s tolerance%s",
                  c.distance_to_mean_m, c.by_mean ? "<=" : ">", c.mean_radius_m,
                  c.distance_to_line_m, c.by_line ? "<=" : ">",
                  c.outlier_left_out >= 0 ? " (one stray position left out)" : "");
  }
  return buf;
}

// The paper's test of p against a set of positions considered complete.
StatsCheck check_points(std::span<const StampedPosition> points, const Eigen::Vector3d& p,
                        std::int64_t stamp_ns, const TrackerParams& params) {
  StatsCheck c;
  c.register_full = true;
  const auto stats = compute_stats(points);
  if (!stats) return c;
  c.sigma_m = stats->sigma_m;
  c.line_rms_m = stats->line_rms_m;
  c.steps_plausible = steps_plausible(points, params);
  c.static_cluster = c.sigma_m <= params.max_static_spread_m;
  // A line needs a direction: the points must spread more along it than across it.
  c.clean_line = c.line_rms_m <= params.line_tolerance_m && stats->line_extent_m > c.line_rms_m;
  const auto& newest = points.back();
  c.jump_plausible =
      (p - newest.position_m).norm() <= max_jump_m(params, stamp_ns - newest.stamp_ns);
  // Five noisy samples of a still ball give an unreliable, often tiny sigma;
  // the floor stands for the detector's own noise so noise alone never rejects.
  const double floor_m =
      std::max(params.sigma_floor_m, params.sigma_floor_fraction * stats->mean_m.norm());
  c.mean_radius_m = std::max(c.sigma_m, floor_m);
  c.distance_to_mean_m = (p - stats->mean_m).norm();
  c.distance_to_line_m = distance_to_line(p, stats->mean_m, stats->line_direction);
  const bool usable = c.steps_plausible && c.jump_plausible;
  c.by_mean = usable && c.static_cluster && c.distance_to_mean_m <= c.mean_radius_m;
  c.by_line = usable && c.clean_line && c.distance_to_line_m <= params.line_tolerance_m;
  c.accepted = c.by_mean || c.by_line;
  return c;
}

}  // namespace

double max_jump_m(const TrackerParams& params, std::int64_t dt_ns) {
  const double dt_s = static_cast<double>(std::max<std::int64_t>(dt_ns, 0)) * 1e-9;
  return params.jump_margin_m + params.max_ball_speed_mps * dt_s;
}

StatsCheck check_position(const PositionRegister& reg, const Eigen::Vector3d& p,
                          std::int64_t stamp_ns, const TrackerParams& params, int max_outliers,
                          int min_positions) {
  const int needed = min_positions > 0 ? std::min(min_positions, reg.capacity()) : reg.capacity();
  const bool enough = reg.size() >= needed;
  StatsCheck c;
  if (enough) c = check_points(reg.entries(), p, stamp_ns, params);
  // A clean register that rejects p has spoken; only a register spoiled by one stray
  // detection (inconsistent, or holding a position off the line of the others) is given a
  // second look without it.
  if (reg.full() && !c.accepted && max_outliers > 0 &&
      (!register_consistent(c) || holds_stray(reg.entries(), params))) {
    const auto& all = reg.entries();
    std::vector<StampedPosition> rest;
    for (std::size_t skip = 0; skip < all.size(); ++skip) {
      rest.clear();
      for (std::size_t i = 0; i < all.size(); ++i) {
        if (i != skip) rest.push_back(all[i]);
      }
      StatsCheck r = check_points(rest, p, stamp_ns, params);
      if (r.accepted) {
        r.outlier_left_out = static_cast<int>(skip);
        c = r;
        break;
      }
    }
  }
  c.register_full = enough;
  c.reason = describe(c, reg.size(), needed);
  return c;
}

}  // namespace stereoball::tracker
