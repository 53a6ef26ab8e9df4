#include "ball_detector/core/p2p_rules.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cstdlib>

namespace stereoball::ball_detector {

int count_window_points(const BitImage& edges, int x, int y, int k) {
  const int n = 2 * k + 1;
  int count = 0;
  for (int r = y - k; r <= y + k; ++r) count += std::popcount(edges.bits(r, x - k, n));
  return count;
}

int collect_window_points(const BitImage& edges, int x, int y, int k, std::span<WindowPoint> out) {
  const int n = 2 * k + 1;
  int used = 0;
  for (int r = -k; r <= k; ++r) {
    std::uint64_t bits = edges.bits(y + r, x - k, n);
    while (bits != 0 && used < static_cast<int>(out.size())) {
      const int c = std::countr_zero(bits);
      bits &= bits - 1;
      out[used++] = WindowPoint{c - k, r};
    }
  }
  return used;
}

namespace {

// Grows seed along the set bits of row (both directions) until blocked: a run fill.
inline std::uint64_t fill_runs(std::uint64_t seed, std::uint64_t row) {
  seed &= row;
  for (std::uint64_t prev = 0; seed != prev;) {
    prev = seed;
    seed |= ((seed << 1) | (seed >> 1)) & row;
  }
  return seed;
}

// The bits of row 8-connected to a neighbour row's mask.
inline std::uint64_t touching(std::uint64_t neighbour, std::uint64_t row) {
  return fill_runs(neighbour | (neighbour << 1) | (neighbour >> 1), row);
}

}  // namespace

int connected_window_rows(const BitImage& edges, int x, int y, int k, std::span<std::uint64_t> rows,
                          int stop_above) {
  const int n = 2 * k + 1;
  if (static_cast<int>(rows.size()) < n) return 0;
  std::array<std::uint64_t, 64> window{};
  for (int r = 0; r < n; ++r) {
    window[static_cast<std::size_t>(r)] = edges.bits(y - k + r, x - k, n);
    rows[static_cast<std::size_t>(r)] = 0;
  }
  rows[static_cast<std::size_t>(k)] =
      fill_runs(std::uint64_t{1} << k, window[static_cast<std::size_t>(k)]);
  int count = std::popcount(rows[static_cast<std::size_t>(k)]);
  // Flood fill by alternating sweeps from the centre row down and up, each row grown from its
  // neighbour and then along its own runs; an arc through a window converges in one or two.
  for (bool grew = true; grew && count <= stop_above;) {
    grew = false;
    auto grow_row = [&](int r, int from) {
      const auto ri = static_cast<std::size_t>(r);
      const std::uint64_t add =
          touching(rows[static_cast<std::size_t>(from)], window[ri]) & ~rows[ri];
      if (add == 0) return;
      const std::uint64_t grown = fill_runs(rows[ri] | add, window[ri]);
      count += std::popcount(grown) - std::popcount(rows[ri]);
      rows[ri] = grown;
      grew = true;
    };
    for (int r = 1; r < n; ++r) grow_row(r, r - 1);
    for (int r = n - 2; r >= 0; --r) grow_row(r, r + 1);
  }
  return count;
}

int collect_masked_points(std::span<const std::uint64_t> rows, int k, std::span<WindowPoint> out) {
  const int n = std::min(2 * k + 1, static_cast<int>(rows.size()));
  int used = 0;
  for (int r = 0; r < n; ++r) {
    std::uint64_t bits = rows[static_cast<std::size_t>(r)];
    while (bits != 0 && used < static_cast<int>(out.size())) {
      const int c = std::countr_zero(bits);
      bits &= bits - 1;
      out[used++] = WindowPoint{c - k, r - k};
    }
  }
  return used;
}

std::optional<ChordEnds> find_chord_ends(std::span<const WindowPoint> points) {
  if (points.empty()) return std::nullopt;
  const WindowPoint* a = &points[0];
  for (const auto& p : points)
    if (l1_distance(p) > l1_distance(*a)) a = &p;
  const WindowPoint* b = nullptr;
  for (const auto& p : points)
    if (opposite_sign(p, *a) && (b == nullptr || l1_distance(p) > l1_distance(*b))) b = &p;
  if (b == nullptr) return std::nullopt;
  return ChordEnds{*a, *b};
}

bool is_straight_segment(const WindowPoint& a, const WindowPoint& b) {
  const int dx = b.x - a.x;
  const int dy = b.y - a.y;
  const int lhs = std::abs(b.y * dx - b.x * dy);
  return lhs <= std::min(std::abs(dx), std::abs(dy));
}

VoteLine perpendicular_bisector(const WindowPoint& a, const WindowPoint& b) {
  // Perpendicular of AB = (dx, dy) is (-dy, dx); C kept doubled to stay on the integer grid.
  return VoteLine{a.x + b.x, a.y + b.y, -(b.y - a.y), b.x - a.x};
}

std::optional<VoteLine> orient_to_concave_side(const VoteLine& line) {
  // O is on the arc and C inside the chord, so the centre lies on C's side of O.
  const int side = line.nx * line.c2x + line.ny * line.c2y;
  if (side == 0) return std::nullopt;
  if (side > 0) return line;
  return VoteLine{line.c2x, line.c2y, -line.nx, -line.ny};
}

std::optional<VoteLine> analyse_window(std::span<const WindowPoint> points, int k) {
  if (!window_count_ok(static_cast<int>(points.size()), k)) return std::nullopt;
  const auto ends = find_chord_ends(points);
  if (!ends) return std::nullopt;
  if (is_straight_segment(ends->a, ends->b)) return std::nullopt;
  return orient_to_concave_side(perpendicular_bisector(ends->a, ends->b));
}

cv::Mat box_filter(const cv::Mat& accumulator, int size_px) {
  cv::Mat smoothed;
  cv::boxFilter(accumulator, smoothed, CV_32S, cv::Size(size_px, size_px), cv::Point(-1, -1), false,
                cv::BORDER_CONSTANT);
  return smoothed;
}

cv::Point global_maximum(const cv::Mat& smoothed) {
  cv::Point best(0, 0);
  int best_v = -1;
  for (int y = 0; y < smoothed.rows; ++y) {
    const int* row = smoothed.ptr<int>(y);
    for (int x = 0; x < smoothed.cols; ++x)
      if (row[x] > best_v) {
        best_v = row[x];
        best = {x, y};
      }
  }
  return best;
}

}  // namespace stereoball::ball_detector
