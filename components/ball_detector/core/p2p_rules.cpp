#include "ball_detector/core/p2p_rules.hpp"

#include "ball_detector/core/cpu_dispatch.hpp"
#include "ball_detector/core/voting.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <cstdlib>
#include <utility>
#include <vector>

#if SB_HAVE_AVX2_KERNELS
#include <immintrin.h>
#endif

namespace stereoball::ball_detector {

int window_rows(const BitImage& edges, int x, int y, int k, std::span<std::uint64_t> rows) {
  const int n = 2 * k + 1;
  int count = 0;
  // One load per row where it fits (short_bits): bits() takes a second word when the run
  // crosses one, a branch taken at random for a wide window.
  const bool short_rows = n <= 57;
  for (int r = 0; r < n; ++r) {
    const std::uint64_t bits =
        short_rows ? edges.short_bits(y - k + r, x - k, n) : edges.bits(y - k + r, x - k, n);
    rows[static_cast<std::size_t>(r)] = bits;
    count += std::popcount(bits);
  }
  return count;
}

int count_window_points(const BitImage& edges, int x, int y, int k) {
  const int n = 2 * k + 1;
  int count = 0;
  for (int r = y - k; r <= y + k; ++r) count += std::popcount(edges.bits(r, x - k, n));
  return count;
}

int collect_window_points(const BitImage& edges, int x, int y, int k, std::span<WindowPoint> out) {
  std::array<std::uint64_t, 64> rows{};
  window_rows(edges, x, y, k, rows);
  return collect_masked_points(std::span<const std::uint64_t>(rows.data(), 2 * k + 1), k, out);
}

namespace {

// The bits of row in the runs (maximal sets of adjacent bits) that seed touches; runs are at
// most 2^Steps bits long (a window row: 2k+1 <= 2^Steps).
template <int Steps>
[[gnu::always_inline]] inline std::uint64_t fill_runs(std::uint64_t seed, std::uint64_t row) {
  seed &= row;
  // Toward higher bits: adding the seeds carries through the rest of each seeded run, clearing
  // it in the sum (seed bits themselves may be cleared too; the downward fill keeps them).
  const std::uint64_t up = row & ~(row + seed);
  // Toward lower bits: doubling (Kogge-Stone) steps; after the step of shift s a seed has
  // reached 2s - 1 bits down, enough once 2s >= the longest run. A compile-time count unrolls
  // them with constant shifts. A step that adds no bit ends the fill: below each seeded run's
  // lowest seed the run is then shorter than that step's shift (else the bit that far below
  // the seed would have been added), so all of it is in already. An arc crosses a row in a
  // pixel or two: most fills end after the first step.
  std::uint64_t fill = seed;
  std::uint64_t through = row;
  // Both lambdas inlined by force: left to GCC, the unrolled steps became a call per fill
  // once the translation unit grew (their cost doubled).
  [&]<int... I>(std::integer_sequence<int, I...>) __attribute__((always_inline)) {
    (void)(...&& [&]() __attribute__((always_inline)) {
      const std::uint64_t before = fill;
      fill |= through & (fill >> (1 << I));
      through &= through >> (1 << I);
      return fill != before;
    }());
  }
  (std::make_integer_sequence<int, Steps>{});
  return up | fill;
}

// The bits of row 8-connected to a neighbour row's mask.
template <int Steps>
[[gnu::always_inline]] inline std::uint64_t touching(std::uint64_t neighbour, std::uint64_t row) {
  return fill_runs<Steps>(neighbour | (neighbour << 1) | (neighbour >> 1), row);
}

// Whether no window pixel outside the sweeps' rows touches them (8-neighbourhood): a dilation
// test, cheaper than growing again. Each row holds whole runs, among them every run touching its
// neighbour toward the centre row, so only its outer neighbour can touch a bit it lacks (an arc
// turning back): one test per pair of adjacent rows, from the outer row.
bool sweeps_closed(std::span<const std::uint64_t> window, std::span<const std::uint64_t> rows,
                   int k) {
  auto spread = [](std::uint64_t m) { return m | (m << 1) | (m >> 1); };
  const auto centre = static_cast<std::size_t>(k);
  for (std::size_t i = 1; i <= centre; ++i) {
    const std::size_t down = centre + i, up = centre - i;
    if (((spread(rows[down]) & window[down - 1] & ~rows[down - 1]) |
         (spread(rows[up]) & window[up + 1] & ~rows[up + 1])) != 0)
      return false;
  }
  return true;
}

// connected_rows for windows of n <= 2^Steps columns (checked by the caller).
template <int Steps>
int connected_rows_steps(std::span<const std::uint64_t> window, int k,
                         std::span<std::uint64_t> rows, int stop_above) {
  const int n = 2 * k + 1;
  const auto centre = static_cast<std::size_t>(k);
  rows[centre] = fill_runs<Steps>(std::uint64_t{1} << k, window[centre]);
  int count = std::popcount(rows[centre]);
  // One sweep down and one up from the centre row complete an arc that crosses each row once,
  // the case that matters; a component that turns back (a U) is finished by the worklist below.
  // The two sweeps run interleaved: each row's fill waits on the previous row's, and two
  // independent chains keep the CPU busy while one waits. Every row the sweeps pass is
  // written (0 once a sweep has died out), the rows past them cleared after: no clearing first.
  std::uint64_t below = rows[centre], above = rows[centre];
  std::size_t i = 1;
  for (; i <= centre && (below | above) != 0 && count <= stop_above; ++i) {
    rows[centre + i] = below = below != 0 ? touching<Steps>(below, window[centre + i]) : 0;
    rows[centre - i] = above = above != 0 ? touching<Steps>(above, window[centre - i]) : 0;
    count += std::popcount(below) + std::popcount(above);
  }
  for (; i <= centre; ++i) rows[centre + i] = rows[centre - i] = 0;
  if (count > stop_above || sweeps_closed(window, rows, k)) return count;
  // Worklist of rows whose mask grew: each grows its two neighbours. Rows are run-closed, so
  // a neighbour's new bits are the runs touching the grown row.
  std::uint64_t pending = (std::uint64_t{1} << n) - 1;
  while (pending != 0 && count <= stop_above) {
    const int r = std::countr_zero(pending);
    pending &= pending - 1;
    for (const int next : {r - 1, r + 1}) {
      if (next < 0 || next >= n) continue;
      const auto ni = static_cast<std::size_t>(next);
      const std::uint64_t grown =
          rows[ni] | touching<Steps>(rows[static_cast<std::size_t>(r)], window[ni]);
      if (grown == rows[ni]) continue;
      count += std::popcount(grown) - std::popcount(rows[ni]);
      rows[ni] = grown;
      pending |= std::uint64_t{1} << next;
    }
  }
  return count;
}

#if SB_HAVE_AVX2_KERNELS
// connected_rows for windows of 2k + 1 <= 8 * Regs rows of at most 31 pixels, one row per 32-bit
// lane (row 8 j + i in lane i of register j): the component through O grown one ring of
// neighbours at a time, every row at once (the sweeps' fill waits on the row before, a chain
// of a few dozen instructions per row of a wide window). The first k rounds are not tested (an
// arc through O needs about that many); then each round is tested for no change and for a
// count above stop_above. The masks written are the component (partial above stop_above).
template <int Regs>
SB_TARGET_AVX2 int connected_rows_avx2(std::span<const std::uint64_t> window, int k,
                                       std::span<std::uint64_t> rows, int stop_above) {
  const int n = 2 * k + 1;
  alignas(32) std::array<std::uint32_t, 8 * Regs> lanes{};
  for (int r = 0; r < n; ++r)
    lanes[static_cast<std::size_t>(r)] = static_cast<std::uint32_t>(window[static_cast<size_t>(r)]);
  __m256i w[Regs], g[Regs];
  for (int j = 0; j < Regs; ++j)
    w[j] = _mm256_load_si256(reinterpret_cast<const __m256i*>(lanes.data() + 8 * j));
  lanes.fill(0);
  lanes[static_cast<std::size_t>(k)] =
      static_cast<std::uint32_t>(window[static_cast<size_t>(k)]) & (std::uint32_t{1} << k);
  for (int j = 0; j < Regs; ++j)
    g[j] = _mm256_load_si256(reinterpret_cast<const __m256i*>(lanes.data() + 8 * j));
  // Lane i takes lane i - 1 (lane 0: lane 7, replaced by the register before's) and lane i + 1.
  const __m256i from_above = _mm256_setr_epi32(7, 0, 1, 2, 3, 4, 5, 6);
  const __m256i from_below = _mm256_setr_epi32(1, 2, 3, 4, 5, 6, 7, 0);
  const auto grow = [&](__m256i* next) SB_TARGET_AVX2 {
    __m256i wide[Regs], above[Regs], below[Regs];
    for (int j = 0; j < Regs; ++j) {
      wide[j] = _mm256_or_si256(
          g[j], _mm256_or_si256(_mm256_slli_epi32(g[j], 1), _mm256_srli_epi32(g[j], 1)));
      above[j] = _mm256_permutevar8x32_epi32(wide[j], from_above);
      below[j] = _mm256_permutevar8x32_epi32(wide[j], from_below);
    }
    for (int j = 0; j < Regs; ++j) {
      const __m256i up =
          _mm256_blend_epi32(above[j], j > 0 ? above[j - 1] : _mm256_setzero_si256(), 0x01);
      const __m256i down =
          _mm256_blend_epi32(below[j], j + 1 < Regs ? below[j + 1] : _mm256_setzero_si256(), 0x80);
      next[j] = _mm256_and_si256(_mm256_or_si256(wide[j], _mm256_or_si256(up, down)), w[j]);
    }
  };
  const auto count_of = [&](const __m256i* v) SB_TARGET_AVX2 {
    int count = 0;
    for (int j = 0; j < Regs; ++j)
      count += std::popcount(static_cast<std::uint64_t>(_mm256_extract_epi64(v[j], 0))) +
               std::popcount(static_cast<std::uint64_t>(_mm256_extract_epi64(v[j], 1))) +
               std::popcount(static_cast<std::uint64_t>(_mm256_extract_epi64(v[j], 2))) +
               std::popcount(static_cast<std::uint64_t>(_mm256_extract_epi64(v[j], 3)));
    return count;
  };
  for (int i = 0; i < k; ++i) {
    __m256i next[Regs];
    grow(next);
    for (int j = 0; j < Regs; ++j) g[j] = next[j];
  }
  int count = 0;
  for (;;) {
    __m256i next[Regs];
    grow(next);
    __m256i changed = _mm256_setzero_si256();
    for (int j = 0; j < Regs; ++j) {
      changed = _mm256_or_si256(changed, _mm256_xor_si256(next[j], g[j]));
      g[j] = next[j];
    }
    count = count_of(g);
    if (_mm256_testz_si256(changed, changed) || count > stop_above) break;
  }
  for (int j = 0; j < Regs; ++j)
    _mm256_store_si256(reinterpret_cast<__m256i*>(lanes.data() + 8 * j), g[j]);
  for (int r = 0; r < n; ++r) rows[static_cast<size_t>(r)] = lanes[static_cast<std::size_t>(r)];
  return count;
}
#endif

}  // namespace

int connected_rows(std::span<const std::uint64_t> window, int k, std::span<std::uint64_t> rows,
                   int stop_above) {
#if SB_HAVE_AVX2_KERNELS
  const int n = 2 * k + 1;
  if (n >= 13 && n <= 31 && static_cast<int>(rows.size()) >= n &&
      static_cast<int>(window.size()) >= n && cpu_has_avx2()) {
    if (n <= 16) return connected_rows_avx2<2>(window, k, rows, stop_above);
    if (n <= 24) return connected_rows_avx2<3>(window, k, rows, stop_above);
    return connected_rows_avx2<4>(window, k, rows, stop_above);
  }
#endif
  return connected_rows_plain(window, k, rows, stop_above);
}

int connected_rows_plain(std::span<const std::uint64_t> window, int k,
                         std::span<std::uint64_t> rows, int stop_above) {
  const int n = 2 * k + 1;
  if (static_cast<int>(rows.size()) < n || static_cast<int>(window.size()) < n || n > 63) return 0;
  // The fewest doubling steps that span a row of n bits (a run is at most n long).
  switch (std::bit_width(static_cast<unsigned>(n - 1))) {
    case 0:
    case 1:
    case 2:
      return connected_rows_steps<2>(window, k, rows, stop_above);
    case 3:
      return connected_rows_steps<3>(window, k, rows, stop_above);
    case 4:
      return connected_rows_steps<4>(window, k, rows, stop_above);
    case 5:
      return connected_rows_steps<5>(window, k, rows, stop_above);
    default:
      return connected_rows_steps<6>(window, k, rows, stop_above);
  }
}

int orientation_bin(int gx, int gy) {
  // Without branches (bitwise tests, a negation by mask): an edge's orientation is a coin toss
  // to the branch predictor. The bin counts the tangent thresholds fy reaches, which grow with
  // ax (0.41421356f * ax <= ax <= 2.41421356f * ax), so the count is the comparison chain's
  // answer; 7 - b is 7 ^ b for b in [0, 3].
  const int flip =
      -(static_cast<int>(gy < 0) | (static_cast<int>(gy == 0) & static_cast<int>(gx < 0)));
  gx = (gx ^ flip) - flip;
  gy = (gy ^ flip) - flip;
  const float ax = static_cast<float>(gx < 0 ? -gx : gx), fy = static_cast<float>(gy);
  const int b = static_cast<int>(fy >= 0.41421356f * ax) + static_cast<int>(fy >= ax) +
                static_cast<int>(fy >= 2.41421356f * ax);
  return b ^ (7 & -static_cast<int>(gx < 0));
}

void near_orientation_planes(const EdgeMap& edges, std::array<BitImage, kOrientationBins>& planes) {
  const BitImage& bits = edges.bits;
  const int w = bits.width(), h = bits.height();
  for (BitImage& plane : planes) plane.reset(w, h);
  for (int y = 0; y < h; ++y) {
    const std::uint64_t* row = bits.row(y);
    const short* gx = edges.dx.ptr<short>(y);
    const short* gy = edges.dy.ptr<short>(y);
    for (int wi = 0; wi * 64 < w; ++wi) {
      if (row[wi] == 0) continue;
      // The word's points by bin, then each plane's word at once: one store per plane and word
      // instead of one per plane and point.
      std::array<std::uint64_t, kOrientationBins> by_bin{};
      for (std::uint64_t word = row[wi]; word != 0; word &= word - 1) {
        const int bit = std::countr_zero(word);
        const int x = wi * 64 + bit;
        by_bin[static_cast<std::size_t>(orientation_bin(gx[x], gy[x]))] |= std::uint64_t{1} << bit;
      }
      for (int b = 0; b < kOrientationBins; ++b) {
        std::uint64_t near = 0;
        for (int d = -kOrientationSlackBins; d <= kOrientationSlackBins; ++d)
          near |= by_bin[static_cast<std::size_t>((b + d + kOrientationBins) % kOrientationBins)];
        planes[static_cast<std::size_t>(b)].mutable_row(y)[wi] = near;
      }
    }
  }
}

int connected_window_rows(const BitImage& edges, int x, int y, int k, std::span<std::uint64_t> rows,
                          int stop_above) {
  const int n = 2 * k + 1;
  if (static_cast<int>(rows.size()) < n) return 0;
  std::array<std::uint64_t, 64> window{};
  window_rows(edges, x, y, k, window);
  return connected_rows(std::span<const std::uint64_t>(window.data(), n), k, rows, stop_above);
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

std::optional<ChordEnds> chord_ends_of_rows(std::span<const std::uint64_t> rows, int k) {
  const int n = std::min(2 * k + 1, static_cast<int>(rows.size()));
  // Candidates in raster order (a row's lowest bit before its highest), strictly better
  // replaces: the first point on ties, as find_chord_ends. The best's distance is kept (-1: no
  // point yet) rather than measured again for every candidate.
  auto consider = [](int x, int y, WindowPoint& best, int& best_d) {
    const int d = (x < 0 ? -x : x) + (y < 0 ? -y : y);
    if (d > best_d) {
      best = {x, y};
      best_d = d;
    }
  };
  WindowPoint a{};
  int a_d = -1;
  for (int r = 0; r < n; ++r) {
    const std::uint64_t bits = rows[static_cast<std::size_t>(r)];
    if (bits == 0) continue;
    consider(std::countr_zero(bits) - k, r - k, a, a_d);
    consider(63 - std::countl_zero(bits) - k, r - k, a, a_d);
  }
  if (a_d < 0) return std::nullopt;
  WindowPoint b{};
  int b_d = -1;
  for (int r = 0; r < n; ++r) {
    const std::uint64_t bits = rows[static_cast<std::size_t>(r)];
    if (bits == 0) continue;
    const int y = r - k;
    const int lo = std::countr_zero(bits) - k;
    const int hi = 63 - std::countl_zero(bits) - k;
    if (y * a.y < 0) {  // the whole row is on the other side vertically
      consider(lo, y, b, b_d);
      consider(hi, y, b, b_d);
    } else if (a.x > 0 && lo < 0) {  // farthest point left of O
      consider(lo, y, b, b_d);
    } else if (a.x < 0 && hi > 0) {  // farthest point right of O
      consider(hi, y, b, b_d);
    }
  }
  if (b_d < 0) return std::nullopt;
  return ChordEnds{a, b};
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

namespace {

// out[x] = from[x] + ... + from[x + N - 1]; a compile-time N lets the compiler unroll and
// vectorise (a run-time count made the whole filter slower than cv::boxFilter). Inlined into
// sum_columns so that each of its CPU copies gets its own.
template <int N>
[[gnu::always_inline]] inline void sum_columns_n(const int* __restrict from, int* __restrict out,
                                                 int w) {
  for (int x = 0; x < w; ++x) {
    int sum = 0;
    for (int t = 0; t < N; ++t) sum += from[x + t];
    out[x] = sum;
  }
}

SB_AVX2_CLONE void sum_columns(const int* from, int* out, int w, int n) {
  switch (n) {
    case 1:
      return sum_columns_n<1>(from, out, w);
    case 3:
      return sum_columns_n<3>(from, out, w);
    case 5:
      return sum_columns_n<5>(from, out, w);
    case 7:
      return sum_columns_n<7>(from, out, w);
    case 9:
      return sum_columns_n<9>(from, out, w);
    default:
      for (int x = 0; x < w; ++x) {
        int sum = 0;
        for (int t = 0; t < n; ++t) sum += from[x + t];
        out[x] = sum;
      }
  }
}

// col[x] += sign * row[x] (sign = +1 or -1).
SB_AVX2_CLONE void add_signed_row(int* __restrict col, const std::uint16_t* __restrict row, int w,
                                  int sign) {
  for (int x = 0; x < w; ++x) col[x] += sign * row[x];
}

// col[x] += entering[x] - leaving[x]: the window moving down a row in one pass over col.
SB_AVX2_CLONE void slide_rows(int* __restrict col, const std::uint16_t* __restrict entering,
                              const std::uint16_t* __restrict leaving, int w) {
  for (int x = 0; x < w; ++x) col[x] += entering[x] - leaving[x];
}

}  // namespace

int box_filter(const cv::Mat& accumulator, int size_px, cv::Mat& smoothed) {
  std::vector<int> row_maxima;
  return box_filter(accumulator, size_px, smoothed, row_maxima);
}

int box_filter(const cv::Mat& accumulator, int size_px, cv::Mat& smoothed,
               std::vector<int>& row_maxima) {
  CV_Assert(accumulator.type() == CV_16UC1 && size_px >= 1 && size_px % 2 == 1);
  const int h = accumulator.rows, w = accumulator.cols, r = size_px / 2;
  smoothed.create(h, w, CV_32SC1);
  row_maxima.resize(static_cast<std::size_t>(h));
  // Separable: running column sums over rows [y - r, y + r], then a horizontal sum of size_px
  // columns. Twice as fast as cv::boxFilter here; the padding makes outside cells zero.
  std::vector<int> padded(static_cast<size_t>(w + 2 * r), 0);
  int* col = padded.data() + r;
  auto add_row = [&](int y, int sign) {
    add_signed_row(col, accumulator.ptr<std::uint16_t>(y), w, sign);
  };
  int maximum = 0;
  for (int y = 0; y < std::min(r, h); ++y) add_row(y, 1);
  for (int y = 0; y < h; ++y) {
    // Rows [y - r, y + r] summed: row y + r enters, row y - r - 1 leaves (one pass when both).
    const bool enters = y + r < h, leaves = y - r - 1 >= 0;
    if (enters && leaves)
      slide_rows(col, accumulator.ptr<std::uint16_t>(y + r),
                 accumulator.ptr<std::uint16_t>(y - r - 1), w);
    else if (enters)
      add_row(y + r, 1);
    else if (leaves)
      add_row(y - r - 1, -1);
    int* out = smoothed.ptr<int>(y);
    sum_columns(padded.data(), out, w, size_px);
    // The maximum while the row is in cache (a second pass, cv::minMaxLoc, took ~0.15 ms).
    row_maxima[static_cast<std::size_t>(y)] = row_maximum(out, w);
    maximum = std::max(maximum, row_maxima[static_cast<std::size_t>(y)]);
  }
  return maximum;
}

std::optional<VoteLine> analyse_window_rows(std::span<const std::uint64_t> rows, int k) {
  int count = 0;
  for (int r = 0; r < std::min(2 * k + 1, static_cast<int>(rows.size())); ++r)
    count += std::popcount(rows[static_cast<std::size_t>(r)]);
  if (!window_count_ok(count, k)) return std::nullopt;
  return vote_line_of_rows(rows, k);
}

std::optional<VoteLine> vote_line_of_rows(std::span<const std::uint64_t> rows, int k) {
  const auto ends = chord_ends_of_rows(rows, k);
  if (!ends) return std::nullopt;
  if (is_straight_segment(ends->a, ends->b)) return std::nullopt;
  return orient_to_concave_side(perpendicular_bisector(ends->a, ends->b));
}

cv::Mat box_filter(const cv::Mat& accumulator, int size_px) {
  cv::Mat smoothed;
  box_filter(accumulator, size_px, smoothed);
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
