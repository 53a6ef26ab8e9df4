#pragma once
// The rules of the Pixel-to-Pixel algorithm (paper section III-D/E), one function each.
// Window coordinates: origin O at the centre edge point, x to the right, y down.

#include "ball_detector/core/edge_map.hpp"

#include <opencv2/core.hpp>

#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <optional>
#include <span>
#include <vector>

namespace stereoball::ball_detector {

/// An edge point of a window, relative to the window centre O, pixels.
struct WindowPoint {
  int x = 0;
  int y = 0;
  friend bool operator==(const WindowPoint&, const WindowPoint&) = default;
};

/// The two chord ends A and B picked in a window.
struct ChordEnds {
  WindowPoint a;
  WindowPoint b;
};

/// The line to plot: through the chord midpoint C, perpendicular to AB, oriented to the concave
/// side.
struct VoteLine {
  int c2x = 0;  ///< 2 * C.x (integer: C lies on a half-pixel grid), pixels
  int c2y = 0;  ///< 2 * C.y, pixels
  int nx = 0;   ///< direction toward the concave side (not normalised), x component
  int ny = 0;   ///< direction toward the concave side, y component
};

/// The 2k+1 rows of the window centred on (x, y) as bit masks (bit c of rows[r] = pixel
/// (c - k, r - k)); the window must lie inside, rows must hold 2k+1 entries. Returns the
/// window's number of edge points (step 4's count, taken while the rows are read).
int window_rows(const BitImage& edges, int x, int y, int k, std::span<std::uint64_t> rows);

/// Number of edge points in the (2k+1)^2 window centred on (x, y); the window must lie inside.
int count_window_points(const BitImage& edges, int x, int y, int k);

/// Rule of step 4: a single one-pixel-thick arc crossing the window has exactly 2k+1 points.
inline bool window_count_ok(int count, int k) {
  return count == 2 * k + 1;
}

/// Collects the edge points of the window (raster order) into out; returns how many (<=
/// out.size()).
int collect_window_points(const BitImage& edges, int x, int y, int k, std::span<WindowPoint> out);

/// Addition: the window's edge points 8-connected to O, as one bit mask per window row (bit c
/// of rows[r] = pixel (c - k, r - k)); returns how many. Lets the count rule judge the arc through
/// O alone when unrelated edges (texture, a line passing by) share the window. Stops growing
/// once more than stop_above are found (then returns a count above it, masks partial).
int connected_window_rows(const BitImage& edges, int x, int y, int k, std::span<std::uint64_t> rows,
                          int stop_above = 64 * 64);

/// connected_window_rows on window rows already read (window_rows); k <= 31. Windows of 13 to 31
/// pixels grow all rows at once where AVX2 runs (the same masks and count as
/// connected_rows_plain below stop_above, a count above it when it does).
int connected_rows(std::span<const std::uint64_t> window, int k, std::span<std::uint64_t> rows,
                   int stop_above = 64 * 64);

/// connected_rows row by row (a sweep down and up from O, then a worklist): every k, any CPU.
int connected_rows_plain(std::span<const std::uint64_t> window, int k,
                         std::span<std::uint64_t> rows, int stop_above = 64 * 64);

/// Collects the points of connected_window_rows' masks (raster order); returns how many.
int collect_masked_points(std::span<const std::uint64_t> rows, int k, std::span<WindowPoint> out);

/// The paper's cheap distance from O: |x| + |y|.
inline int l1_distance(const WindowPoint& p) {
  return (p.x < 0 ? -p.x : p.x) + (p.y < 0 ? -p.y : p.y);
}

/// Whether at least one homologous coordinate of p and q has strictly opposite sign.
inline bool opposite_sign(const WindowPoint& p, const WindowPoint& q) {
  return p.x * q.x < 0 || p.y * q.y < 0;
}

/// Step 5: A = the point farthest from O (L1, first in raster order on ties); B = the farthest
/// point with at least one coordinate of opposite sign to A. nullopt if no such B (angular point).
std::optional<ChordEnds> find_chord_ends(std::span<const WindowPoint> points);

/// find_chord_ends of the points held in window row masks (as collect_masked_points lays them
/// out), without collecting them: in a row, the farthest point (L1) is its lowest or highest
/// bit, so only those two are looked at. Same A and B, ties included.
std::optional<ChordEnds> chord_ends_of_rows(std::span<const std::uint64_t> rows, int k);

/// Step 6, eq. (3): A, B and O are aligned when |yB(xB-xA) - xB(yB-yA)| <= min(|xB-xA|, |yB-yA|).
bool is_straight_segment(const WindowPoint& a, const WindowPoint& b);

/// Eq. (1) and the perpendicular to AB through the midpoint C (orientation not yet chosen).
VoteLine perpendicular_bisector(const WindowPoint& a, const WindowPoint& b);

/// Step 7: orients the line toward the concave side (the side of C as seen from O, which lies on
/// the arc); nullopt when C coincides with O's projection (no concavity).
std::optional<VoteLine> orient_to_concave_side(const VoteLine& line);

/// Steps 4-7 on one window's points: the vote line, or nullopt if any rule rejects the window.
std::optional<VoteLine> analyse_window(std::span<const WindowPoint> points, int k);

/// analyse_window on window row masks (see chord_ends_of_rows).
std::optional<VoteLine> analyse_window_rows(std::span<const std::uint64_t> rows, int k);

/// Steps 5-7 of analyse_window_rows, for a caller that has already counted the window's points
/// (the count rule holds).
std::optional<VoteLine> vote_line_of_rows(std::span<const std::uint64_t> rows, int k);

/// Windows of k <= kPackedMaxK (at most 7 x 7 pixels) held in one word: window row r in byte
/// r, bit c of it = pixel (c - k, r - k), so raster order is bit order. The eighth column and
/// row stay clear, so a pixel shifted by one column or row never wraps into the window.
constexpr int kPackedMaxK = 3;

/// The window centred on (x, y) packed (k <= kPackedMaxK); the window must lie inside.
inline std::uint64_t packed_window(const BitImage& edges, int x, int y, int k) {
  const int n = 2 * k + 1;
  std::uint64_t window = 0;
  for (int r = 0; r < n; ++r) window |= edges.short_bits(y - k + r, x - k, n) << (8 * r);
  return window;
}

/// connected_rows of a packed window: its points 8-connected to O (into component) and how
/// many; once more than stop_above are found, a count above it (component partial).
inline int connected_packed(std::uint64_t window, int k, std::uint64_t& component,
                            int stop_above = 64) {
  // Grown one ring of neighbours at a time: an arc through O is whole after k or so rounds,
  // where the row-by-row fill took a few hundred instructions. The first k rounds run without
  // a test (an arc through O needs about that many, and a test whose answer varies from window
  // to window costs more in mispredictions than the rounds); then until nothing is added.
  const auto grow = [window](std::uint64_t from) {
    const std::uint64_t wide = from | (from << 1) | (from >> 1);
    return (wide | (wide << 8) | (wide >> 8)) & window;
  };
  std::uint64_t grown = window & (std::uint64_t{1} << (9 * k));
  for (int i = 0; i < k; ++i) grown = grow(grown);
  for (;;) {
    const std::uint64_t next = grow(grown);
    const bool done = next == grown || std::popcount(next) > stop_above;
    grown = next;
    if (done) break;
  }
  component = grown;
  return std::popcount(grown);
}

namespace packed_detail {
// Per k: the window bits at each L1 distance from O, and those left of, right of, above and
// below it (strictly).
struct PackedMasks {
  std::array<std::uint64_t, 2 * kPackedMaxK + 1> ring{};
  std::uint64_t left = 0, right = 0, up = 0, down = 0;
};
constexpr std::array<PackedMasks, kPackedMaxK + 1> make_packed_masks() {
  std::array<PackedMasks, kPackedMaxK + 1> all{};
  for (int k = 0; k <= kPackedMaxK; ++k)
    for (int r = 0; r <= 2 * k; ++r)
      for (int c = 0; c <= 2 * k; ++c) {
        const std::uint64_t bit = std::uint64_t{1} << (8 * r + c);
        const int x = c - k, y = r - k;
        PackedMasks& m = all[static_cast<std::size_t>(k)];
        m.ring[static_cast<std::size_t>((x < 0 ? -x : x) + (y < 0 ? -y : y))] |= bit;
        if (x < 0) m.left |= bit;
        if (x > 0) m.right |= bit;
        if (y < 0) m.up |= bit;
        if (y > 0) m.down |= bit;
      }
  return all;
}
inline constexpr std::array<PackedMasks, kPackedMaxK + 1> kPackedMasks = make_packed_masks();
// The first point in raster order of the farthest nonempty ring (points must be nonempty).
inline int farthest_first(std::uint64_t points, const PackedMasks& m, int k) {
  int d = 2 * k;
  while ((points & m.ring[static_cast<std::size_t>(d)]) == 0) --d;
  return std::countr_zero(points & m.ring[static_cast<std::size_t>(d)]);
}
}  // namespace packed_detail

/// chord_ends_of_rows of a packed window: the same A and B, ties included (the farthest ring
/// holding a point, then its first point in raster order: its lowest bit).
inline std::optional<ChordEnds> chord_ends_packed(std::uint64_t window, int k) {
  if (window == 0) return std::nullopt;
  const packed_detail::PackedMasks& m = packed_detail::kPackedMasks[static_cast<std::size_t>(k)];
  const int ai = packed_detail::farthest_first(window, m, k);
  const WindowPoint a{(ai & 7) - k, (ai >> 3) - k};
  // The side masks picked by sign without branches (masks of all ones or none).
  const auto when = [](bool c) { return std::uint64_t{0} - static_cast<std::uint64_t>(c); };
  const std::uint64_t opposite = window & ((m.left & when(a.x > 0)) | (m.right & when(a.x < 0)) |
                                           (m.up & when(a.y > 0)) | (m.down & when(a.y < 0)));
  if (opposite == 0) return std::nullopt;
  const int bi = packed_detail::farthest_first(opposite, m, k);
  return ChordEnds{a, WindowPoint{(bi & 7) - k, (bi >> 3) - k}};
}

/// vote_line_of_rows of a packed window (the count rule already checked).
inline std::optional<VoteLine> vote_line_packed(std::uint64_t window, int k) {
  const auto ends = chord_ends_packed(window, k);
  if (!ends || is_straight_segment(ends->a, ends->b)) return std::nullopt;
  return orient_to_concave_side(perpendicular_bisector(ends->a, ends->b));
}

#if defined(__SIZEOF_INT128__)
#define SB_WIDE_WINDOWS 1
/// Windows of kPackedMaxK < k <= kWideMaxK (at most 11 x 11 pixels) held in one 128-bit word:
/// window row r in bits [n r, n r + n) (n = 2k + 1), bit n r + c = pixel (c - k, r - k), so
/// raster order is bit order. Rows are packed without a spare column: a shift by one column is
/// masked so that no pixel wraps into the next row.
using WideWindow = unsigned __int128;
constexpr int kWideMaxK = 5;

namespace wide_detail {
// Per k: the columns a shift by one may carry a pixel into from the next row (cleared after a
// shift), the window bits at each L1 distance from O, and those left of, right of, above and
// below it (strictly).
struct WideMasks {
  WideWindow not_first_column = 0, not_last_column = 0;
  std::array<WideWindow, 2 * kWideMaxK + 1> ring{};
  WideWindow left = 0, right = 0, up = 0, down = 0;
};
template <int k>
constexpr WideMasks make_wide_masks() {
  constexpr int n = 2 * k + 1;
  WideMasks m;
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) {
      const WideWindow bit = WideWindow{1} << (n * r + c);
      const int x = c - k, y = r - k;
      if (c != 0) m.not_first_column |= bit;
      if (c != n - 1) m.not_last_column |= bit;
      m.ring[static_cast<std::size_t>((x < 0 ? -x : x) + (y < 0 ? -y : y))] |= bit;
      if (x < 0) m.left |= bit;
      if (x > 0) m.right |= bit;
      if (y < 0) m.up |= bit;
      if (y > 0) m.down |= bit;
    }
  return m;
}
template <int k>
inline constexpr WideMasks kWideMasks = make_wide_masks<k>();
inline int popcount_wide(WideWindow w) {
  return std::popcount(static_cast<std::uint64_t>(w)) +
         std::popcount(static_cast<std::uint64_t>(w >> 64));
}
// The lowest set bit's index (w nonempty).
inline int lowest_bit_wide(WideWindow w) {
  const auto low = static_cast<std::uint64_t>(w);
  return low != 0 ? std::countr_zero(low)
                  : 64 + std::countr_zero(static_cast<std::uint64_t>(w >> 64));
}
// The first point in raster order of the farthest nonempty ring (points must be nonempty).
template <int k>
inline int farthest_first_wide(WideWindow points) {
  const WideMasks& m = kWideMasks<k>;
  int d = 2 * k;
  while ((points & m.ring[static_cast<std::size_t>(d)]) == 0) --d;
  return lowest_bit_wide(points & m.ring[static_cast<std::size_t>(d)]);
}
}  // namespace wide_detail

/// The window centred on (x, y) packed wide (kPackedMaxK < k <= kWideMaxK); the window must lie
/// inside.
template <int k>
inline WideWindow wide_window(const BitImage& edges, int x, int y) {
  // Each row read with one load as short_bits() reads it, placed into the two 64-bit halves
  // with constant shifts, the row pointer moved by the row step (no multiply per row).
  constexpr int n = 2 * k + 1;
  if constexpr (std::endian::native != std::endian::little) {
    WideWindow window = 0;
    for (int r = 0; r < n; ++r)
      window |= static_cast<WideWindow>(edges.short_bits(y - k + r, x - k, n)) << (n * r);
    return window;
  }
  const int x0 = x - k;
  const auto* row = reinterpret_cast<const unsigned char*>(edges.row(y - k)) + (x0 >> 3);
  const std::ptrdiff_t step = reinterpret_cast<const unsigned char*>(edges.row(y - k + 1)) -
                              reinterpret_cast<const unsigned char*>(edges.row(y - k));
  const int shift = x0 & 7;
  std::uint64_t low = 0, high = 0;
  for (int r = 0; r < n; ++r, row += step) {
    std::uint64_t v;
    std::memcpy(&v, row, sizeof v);
    v = (v >> shift) & ((std::uint64_t{1} << n) - 1);
    const int at = n * r;
    if (at + n <= 64) {
      low |= v << at;
    } else if (at >= 64) {
      high |= v << (at - 64);
    } else {
      low |= v << at;
      high |= v >> (64 - at);
    }
  }
  return (static_cast<WideWindow>(high) << 64) | low;
}

/// connected_rows of a wide window: its points 8-connected to O (into component) and how many;
/// once more than stop_above are found, a count above it (component partial).
template <int k>
inline int connected_wide(WideWindow window, WideWindow& component, int stop_above = 128) {
  // As connected_packed: grown one ring of neighbours at a time, the first k rounds untested.
  // On the two 64-bit halves by hand: GCC moves a 128-bit value through memory between rounds.
  constexpr int n = 2 * k + 1;
  constexpr int seed = n * k + k;  // O's bit
  static_assert(seed < 64 && n < 64);
  const wide_detail::WideMasks& m = wide_detail::kWideMasks<k>;
  const auto low_of = [](WideWindow w) { return static_cast<std::uint64_t>(w); };
  const auto high_of = [](WideWindow w) { return static_cast<std::uint64_t>(w >> 64); };
  const std::uint64_t window_low = low_of(window), window_high = high_of(window);
  const std::uint64_t first_low = low_of(m.not_first_column),
                      first_high = high_of(m.not_first_column);
  const std::uint64_t last_low = low_of(m.not_last_column), last_high = high_of(m.not_last_column);
  const auto grow = [&](std::uint64_t& low, std::uint64_t& high) {
    const std::uint64_t wide_low =
        low | ((low << 1) & first_low) | (((low >> 1) | (high << 63)) & last_low);
    const std::uint64_t wide_high =
        high | (((high << 1) | (low >> 63)) & first_high) | ((high >> 1) & last_high);
    const std::uint64_t down_low = wide_low << n;
    const std::uint64_t down_high = (wide_high << n) | (wide_low >> (64 - n));
    const std::uint64_t up_low = (wide_low >> n) | (wide_high << (64 - n));
    const std::uint64_t up_high = wide_high >> n;
    low = (wide_low | down_low | up_low) & window_low;
    high = (wide_high | down_high | up_high) & window_high;
  };
  std::uint64_t low = window_low & (std::uint64_t{1} << seed), high = 0;
  for (int i = 0; i < k; ++i) grow(low, high);
  for (;;) {
    std::uint64_t next_low = low, next_high = high;
    grow(next_low, next_high);
    const bool done = (next_low == low && next_high == high) ||
                      std::popcount(next_low) + std::popcount(next_high) > stop_above;
    low = next_low;
    high = next_high;
    if (done) break;
  }
  component = (static_cast<WideWindow>(high) << 64) | low;
  return std::popcount(low) + std::popcount(high);
}

/// chord_ends_of_rows of a wide window: the same A and B, ties included (as chord_ends_packed).
template <int k>
inline std::optional<ChordEnds> chord_ends_wide(WideWindow window) {
  if (window == 0) return std::nullopt;
  constexpr int n = 2 * k + 1;
  const wide_detail::WideMasks& m = wide_detail::kWideMasks<k>;
  const int ai = wide_detail::farthest_first_wide<k>(window);
  const WindowPoint a{ai % n - k, ai / n - k};
  // The side masks picked by sign without branches (masks of all ones or none).
  const auto when = [](bool c) { return WideWindow{0} - static_cast<WideWindow>(c); };
  const WideWindow opposite = window & ((m.left & when(a.x > 0)) | (m.right & when(a.x < 0)) |
                                        (m.up & when(a.y > 0)) | (m.down & when(a.y < 0)));
  if (opposite == 0) return std::nullopt;
  const int bi = wide_detail::farthest_first_wide<k>(opposite);
  return ChordEnds{a, WindowPoint{bi % n - k, bi / n - k}};
}

/// vote_line_of_rows of a wide window (the count rule already checked).
template <int k>
inline std::optional<VoteLine> vote_line_wide(WideWindow window) {
  const auto ends = chord_ends_wide<k>(window);
  if (!ends || is_straight_segment(ends->a, ends->b)) return std::nullopt;
  return orient_to_concave_side(perpendicular_bisector(ends->a, ends->b));
}
#else
#define SB_WIDE_WINDOWS 0
#endif

/// Orientation isolation (addition): orientation bins of 22.5 degrees (modulo 180), and how
/// many bins either side count as aligned.
constexpr int kOrientationBins = 8;
constexpr int kOrientationSlackBins = 2;

/// Bin in [0, 8) of gradient (gx, gy)'s orientation modulo 180 degrees, without atan2:
/// tan(22.5) and tan(67.5) split each quadrant.
int orientation_bin(int gx, int gy);

/// Plane b: the edge points of edges whose orientation bin lies within kOrientationSlackBins of
/// b (circularly); planes are sized to the map.
void near_orientation_planes(const EdgeMap& edges, std::array<BitImage, kOrientationBins>& planes);

/// Step 9: smoothing by an all-ones square mask: each cell becomes the sum of votes in the
/// size_px x size_px box around it (CV_16U in, CV_32S out, zero outside the image).
cv::Mat box_filter(const cv::Mat& accumulator, int size_px);
/// Same into smoothed (its buffer reused when the size is unchanged); size_px odd. Returns the
/// largest smoothed value (0 for an all-zero map).
int box_filter(const cv::Mat& accumulator, int size_px, cv::Mat& smoothed);
/// Same, also giving each smoothed row's largest value (0 if all are below) in row_maxima (one
/// per row), which find_peaks can take instead of scanning the rows for it again.
int box_filter(const cv::Mat& accumulator, int size_px, cv::Mat& smoothed,
               std::vector<int>& row_maxima);

/// Step 9: position of the global maximum of a CV_32S map (first in raster order on ties).
cv::Point global_maximum(const cv::Mat& smoothed);

}  // namespace stereoball::ball_detector
