// The Pixel-to-Pixel detector's votes (paper steps 2-7): each edge point's window judged by the
// count rule (or its arc isolated), its vote line found and plotted into the accumulator, in one
// pass or in row shares run as tasks and joined in one pass's order. Apart from the driver
// (p2p_detector.cpp) because this is the detector's inner loop, read on its own.
#include "ball_detector/core/p2p_detector.hpp"

#include "ball_detector/core/fast_math.hpp"
#include "ball_detector/core/p2p_detector_internal.hpp"
#include "ball_detector/core/voting.hpp"

#include <opencv2/core.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>

namespace stereoball::ball_detector {

using p2p_detail::kMaxK;
using p2p_detail::map_in_store;

void PixelToPixelDetector::vote(int k) {
  vote_rows(k, 0, edges_.bits.height(), [this](float cx, float cy, int nx, int ny) {
    lines_.push_back({cx, cy, nx, ny});
    plot(lines_.back());
  });
}

int PixelToPixelDetector::isolate_max_points_of(int n) const {
  return params_.isolate_arc ? static_cast<int>(params_.isolate_max_points_factor * n) : 0;
}

template <typename F>
void PixelToPixelDetector::for_each_window_centre(int k, int y_begin, int y_end, F&& f) const {
  const BitImage& bits = edges_.bits;
  const int w = bits.width();
  const int y_last = std::min(bits.height() - k, y_end);
  for (int y = std::max(k, y_begin); y < y_last; ++y)
    bits.for_each_set_in_row(y, [&](int x) {
      if (x >= k && x < w - k) f(x, y);
    });
}

template <typename Emit>
void PixelToPixelDetector::vote_rows(int k, int y_begin, int y_end, Emit&& emit) {
  // The packed windows' loops unrolled for each k (p2p_rules.hpp).
  if (k == 1) return vote_packed<1>(y_begin, y_end, emit);
  if (k == 2) return vote_packed<2>(y_begin, y_end, emit);
  if (k == 3) return vote_packed<3>(y_begin, y_end, emit);
  static_assert(kPackedMaxK == 3);
#if SB_WIDE_WINDOWS
  if (k == 4) return vote_wide<4>(y_begin, y_end, emit);
  if (k == 5) return vote_wide<5>(y_begin, y_end, emit);
  static_assert(kWideMaxK == 5);
#endif
  const BitImage& bits = edges_.bits;
  std::array<std::uint64_t, 2 * kMaxK + 1> mask{};
  std::array<std::uint64_t, 2 * kMaxK + 1> rows{};
  const int n = 2 * k + 1;
  const int isolate_max_points = isolate_max_points_of(n);
  for_each_window_centre(k, y_begin, y_end, [&](int x, int y) {
    // The window's rows are read once, step 4's count taken as they are (a popcount per
    // row): far cheaper than collecting points.
    const auto window_bits = std::span(rows.data(), n);
    const int count = window_rows(bits, x, y, k, window_bits);
    // Steps 5-7 read the chord ends straight off the row masks (vote_line_of_rows).
    std::optional<VoteLine> line;
    if (window_count_ok(count, k)) {
      line = vote_line_of_rows(window_bits, k);
    } else if (count > n && count <= isolate_max_points) {
      // Addition: judge the arc through O alone when other edges share the window.
      const int connected = connected_rows(window_bits, k, mask, n);
      // O's aligned component lies inside its component: fewer than n points leave it short too.
      if (connected != n && (connected < n || !params_.isolate_by_orientation ||
                             !isolate_along_orientation(x, y, k, window_bits, mask)))
        return;
      line = vote_line_of_rows(std::span<const std::uint64_t>(mask.data(), n), k);
    } else {
      return;
    }
    if (!line) return;
    // C lies on the half-pixel grid: exact in float for any image size we take.
    emit(static_cast<float>(x + 0.5 * line->c2x), static_cast<float>(y + 0.5 * line->c2y), line->nx,
         line->ny);
  });
}

template <int k, typename Emit>
void PixelToPixelDetector::vote_packed(int y_begin, int y_end, Emit& emit) {
  // vote_rows() for windows that fit one word (p2p_rules.hpp): the same rules on the same points,
  // each a few word operations instead of a loop over rows.
  const BitImage& bits = edges_.bits;
  const int n = 2 * k + 1;
  const int isolate_max_points = isolate_max_points_of(n);
  for_each_window_centre(k, y_begin, y_end, [&](int x, int y) {
    const std::uint64_t window = packed_window(bits, x, y, k);
    const int count = std::popcount(window);
    std::uint64_t arc = window;
    if (count == n) {
      // The count rule holds: the whole window is the arc.
    } else if (count > n && count <= isolate_max_points) {
      // Addition: judge the arc through O alone when other edges share the window.
      const int connected = connected_packed(window, k, arc, n);
      if (connected != n && (connected < n || !params_.isolate_by_orientation ||
                             !isolate_packed<k>(x, y, window, arc)))
        return;
    } else {
      return;
    }
    const std::optional<VoteLine> line = vote_line_packed(arc, k);
    if (!line) return;
    emit(static_cast<float>(x + 0.5 * line->c2x), static_cast<float>(y + 0.5 * line->c2y), line->nx,
         line->ny);
  });
}

template <int k>
bool PixelToPixelDetector::isolate_packed(int x, int y, std::uint64_t window, std::uint64_t& arc) {
  // isolate_along_orientation on a packed window: the points within the slack of O's
  // orientation, then their component through O.
  if (!orientation_ready_) build_orientation_planes();
  const BitImage& near = near_orientation_[static_cast<std::size_t>(
      orientation_bin(edges_.dx.at<short>(y, x), edges_.dy.at<short>(y, x)))];
  const std::uint64_t aligned = window & packed_window(near, x, y, k);
  const int n = 2 * k + 1;
  if (std::popcount(aligned) < n || aligned == window) return false;
  return connected_packed(aligned, k, arc, n) == n;
}

#if SB_WIDE_WINDOWS
template <int k, typename Emit>
void PixelToPixelDetector::vote_wide(int y_begin, int y_end, Emit& emit) {
  // vote_packed() for windows of up to 11 x 11 pixels (p2p_rules.hpp): a 128-bit word instead
  // of a mask per row, the component grown a ring at a time instead of row by row.
  const BitImage& bits = edges_.bits;
  constexpr int n = 2 * k + 1;
  const int isolate_max_points = isolate_max_points_of(n);
  for_each_window_centre(k, y_begin, y_end, [&](int x, int y) {
    const WideWindow window = wide_window<k>(bits, x, y);
    const int count = wide_detail::popcount_wide(window);
    WideWindow arc = window;
    if (count == n) {
      // The count rule holds: the whole window is the arc.
    } else if (count > n && count <= isolate_max_points) {
      // Addition: judge the arc through O alone when other edges share the window.
      const int connected = connected_wide<k>(window, arc, n);
      if (connected != n &&
          (connected < n || !params_.isolate_by_orientation || !isolate_wide<k>(x, y, window, arc)))
        return;
    } else {
      return;
    }
    const std::optional<VoteLine> line = vote_line_wide<k>(arc);
    if (!line) return;
    emit(static_cast<float>(x + 0.5 * line->c2x), static_cast<float>(y + 0.5 * line->c2y), line->nx,
         line->ny);
  });
}

template <int k>
bool PixelToPixelDetector::isolate_wide(int x, int y, WideWindow window, WideWindow& arc) {
  // isolate_packed on a wide window.
  if (!orientation_ready_) build_orientation_planes();
  const BitImage& near = near_orientation_[static_cast<std::size_t>(
      orientation_bin(edges_.dx.at<short>(y, x), edges_.dy.at<short>(y, x)))];
  const WideWindow aligned = window & wide_window<k>(near, x, y);
  constexpr int n = 2 * k + 1;
  if (wide_detail::popcount_wide(aligned) < n || aligned == window) return false;
  return connected_wide<k>(aligned, arc, n) == n;
}
#endif

// Inlined into both callers: the one-run plot() costs what it did before shares existed.
[[gnu::always_inline]] inline void PixelToPixelDetector::plot_into(const VoteLineAt& line,
                                                                   cv::Mat& accumulator,
                                                                   std::int64_t& rays_plotted,
                                                                   std::int64_t& increments,
                                                                   std::vector<Voter>& voters) {
  // A ray meets a cell once: while fewer rays than a cell holds have gone into the zeroed map,
  // none is full and the increments need no saturation test.
  const bool may_be_full = rays_plotted++ >= 0xFFFF;
  const LineDirection& dir = line_direction(line.nx, line.ny);
  increments += plot_ray(accumulator, static_cast<double>(line.cx) + margin_px_,
                         static_cast<double>(line.cy) + margin_px_, dir.ray, radii_.min_px,
                         radii_.max_px, may_be_full);
  voters.push_back({line.cx, line.cy, dir.unit_x, dir.unit_y});
}

void PixelToPixelDetector::plot(const VoteLineAt& line) {
  plot_into(line, accumulator_, rays_plotted_, diag_.increments, voters_);
}

void PixelToPixelDetector::plot(const VoteLineAt& line, cv::Mat& accumulator, VoteShare& share) {
  plot_into(line, accumulator, share.rays_plotted, share.increments, share.voters);
}

void PixelToPixelDetector::fill_directions() {
  const int span = direction_span_;
  for (int nx = -span; nx <= span; ++nx)
    for (int ny = -span; ny <= span; ++ny) (void)line_direction(nx, ny);
}

const PixelToPixelDetector::LineDirection& PixelToPixelDetector::line_direction(int nx, int ny) {
  // A few hundred directions recur over tens of thousands of lines: the square roots and
  // divisions are done once per direction, with the same operations (the same bits).
  const int span = direction_span_;
  const bool in_table = nx >= -span && nx <= span && ny >= -span && ny <= span;
  LineDirection& d =
      in_table ? directions_[static_cast<std::size_t>((nx + span) * (2 * span + 1) + ny + span)]
               : direction_scratch_;
  if (d.ready) return d;
  d.ray = ray_direction(nx, ny);
  const float norm = fast_hypot(static_cast<float>(nx), static_cast<float>(ny));
  d.unit_x = nx / norm;
  d.unit_y = ny / norm;
  d.ready = in_table;
  return d;
}

void PixelToPixelDetector::build_orientation_planes() {
  near_orientation_planes(edges_, near_orientation_);
  orientation_ready_ = true;
}

bool PixelToPixelDetector::isolate_along_orientation(int x, int y, int k,
                                                     std::span<const std::uint64_t> window,
                                                     std::span<std::uint64_t> mask) {
  if (!orientation_ready_) build_orientation_planes();
  const int n = 2 * k + 1;
  // The window's points within the slack of O's orientation: one AND per row with O's plane.
  const BitImage& near = near_orientation_[static_cast<std::size_t>(
      orientation_bin(edges_.dx.at<short>(y, x), edges_.dy.at<short>(y, x)))];
  std::array<std::uint64_t, 2 * kMaxK + 1> aligned;  // rows [0, n) written below, no others read
  int count = 0;
  std::uint64_t dropped = 0;
  for (int i = 0; i < n; ++i) {
    const std::uint64_t all = window[static_cast<std::size_t>(i)];
    const std::uint64_t kept =
        all & (n <= 57 ? near.short_bits(y - k + i, x - k, n) : near.bits(y - k + i, x - k, n));
    aligned[static_cast<std::size_t>(i)] = kept;
    dropped |= all ^ kept;
    count += std::popcount(kept);
  }
  // Nothing dropped: the same window whose component the caller found not to be n points.
  if (count < n || dropped == 0) return false;
  return connected_rows(std::span<const std::uint64_t>(aligned.data(), static_cast<std::size_t>(n)),
                        k, mask, n) == n;
}

void PixelToPixelDetector::vote_on_edges(const VoteTasks& tasks) {
  const cv::Size size = edges_.edges.size();
  map_in_store(accumulator_store_, accumulator_, size.height + 2 * margin_px_,
               size.width + 2 * margin_px_, CV_16UC1);
  rays_plotted_ = 0;
  lines_.clear();
  if (tasks.run && tasks.shares > 1) {
    vote_in_shares(tasks);
  } else {
    accumulator_.setTo(0);
    for (int k : params_.k_values) vote(k);
  }
  votes_ready_ = true;
}

void PixelToPixelDetector::vote_in_shares(const VoteTasks& tasks) {
  const int n = std::min(tasks.shares, VoteTasks::kMaxVoteShares);
  // What the shares read and would otherwise make on first use is made first: they only read.
  // Every line's direction lies in the table (|nx|, |ny| <= 2 k <= direction_span_), never in
  // its shared scratch.
  if (params_.isolate_arc && params_.isolate_by_orientation && !orientation_ready_)
    build_orientation_planes();
  fill_directions();
  const std::vector<std::vector<int>> rows = share_rows(n);
  if (shares_.size() < static_cast<std::size_t>(n)) shares_.resize(static_cast<std::size_t>(n));
  for (int s = 1; s < n; ++s) {
    VoteShare& share = shares_[static_cast<std::size_t>(s)];
    map_in_store(share.store, share.accumulator, accumulator_.rows, accumulator_.cols, CV_16UC1);
  }
  tasks.run(n, [&](int s) { vote_share(s, rows); });
  join_shares(n);
}

std::vector<std::vector<int>> PixelToPixelDetector::share_rows(int n) const {
  // A share's time follows its edge points (each is a window to judge), not its rows.
  const BitImage& bits = edges_.bits;
  const int h = bits.height();
  const int words = (bits.width() + 63) / 64;
  std::vector<std::int64_t> before(static_cast<std::size_t>(h) + 1, 0);  // points in rows < y
  for (int y = 0; y < h; ++y) {
    std::int64_t count = 0;
    for (int i = 0; i < words; ++i) count += std::popcount(bits.row(y)[i]);
    before[static_cast<std::size_t>(y) + 1] = before[static_cast<std::size_t>(y)] + count;
  }
  std::vector<std::vector<int>> rows;
  for (int k : params_.k_values) {
    const int first = std::min(k, h), last = std::max(first, h - k);
    const std::int64_t from = before[static_cast<std::size_t>(first)];
    const std::int64_t total = before[static_cast<std::size_t>(last)] - from;
    std::vector<int> bounds{first};
    for (int s = 1; s < n; ++s) {
      const std::int64_t target = from + total * s / n;
      const auto at =
          std::lower_bound(before.begin() + bounds.back(), before.begin() + last, target);
      bounds.push_back(static_cast<int>(at - before.begin()));
    }
    bounds.push_back(last);
    rows.push_back(std::move(bounds));
  }
  return rows;
}

void PixelToPixelDetector::vote_share(int s, const std::vector<std::vector<int>>& rows) {
  VoteShare& share = shares_[static_cast<std::size_t>(s)];
  cv::Mat& accumulator = s == 0 ? accumulator_ : share.accumulator;
  accumulator.setTo(0);
  share.lines.clear();
  share.voters.clear();
  share.k_ends.clear();
  share.rays_plotted = 0;
  share.increments = 0;
  for (std::size_t j = 0; j < params_.k_values.size(); ++j) {
    vote_rows(params_.k_values[j], rows[j][static_cast<std::size_t>(s)],
              rows[j][static_cast<std::size_t>(s) + 1], [&](float cx, float cy, int nx, int ny) {
                share.lines.push_back({cx, cy, nx, ny});
                plot(share.lines.back(), accumulator, share);
              });
    share.k_ends.push_back(share.lines.size());
  }
}

void PixelToPixelDetector::join_shares(int n) {
  // Lines and voters in the order one task would have made them: k by k, rows in order.
  voters_.clear();
  for (std::size_t j = 0; j < params_.k_values.size(); ++j) {
    for (int s = 0; s < n; ++s) {
      const VoteShare& share = shares_[static_cast<std::size_t>(s)];
      const auto begin = static_cast<std::ptrdiff_t>(j == 0 ? 0 : share.k_ends[j - 1]);
      const auto end = static_cast<std::ptrdiff_t>(share.k_ends[j]);
      lines_.insert(lines_.end(), share.lines.begin() + begin, share.lines.begin() + end);
      voters_.insert(voters_.end(), share.voters.begin() + begin, share.voters.begin() + end);
    }
  }
  // Each cell holds min(votes, 0xFFFF), as one map plotted with saturation does.
  for (int s = 0; s < n; ++s) {
    const VoteShare& share = shares_[static_cast<std::size_t>(s)];
    rays_plotted_ += share.rays_plotted;
    diag_.increments += share.increments;
    if (s > 0) cv::add(accumulator_, share.accumulator, accumulator_);  // saturating for CV_16U
  }
}

}  // namespace stereoball::ball_detector
