#include "ball_detector/core/voting.hpp"

#include "ball_detector/core/cpu_dispatch.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <type_traits>
#include <utility>

#if SB_HAVE_AVX2_KERNELS
#include <immintrin.h>
#endif

namespace stereoball::ball_detector {

namespace {

// std::llround without the library call (one per ray adds up): half away from zero. The
// truncation and x - t are exact for |x| < 2^52.
inline std::int64_t round_half_away(double x) {
  const auto t = static_cast<std::int64_t>(x);
  const double frac = x - static_cast<double>(t);
  return t + (frac >= 0.5 ? 1 : 0) - (frac <= -0.5 ? 1 : 0);
}

}  // namespace

SB_AVX2_CLONE int row_maximum(const int* __restrict row, int w) {
  int best = 0;
  for (int x = 0; x < w; ++x) best = std::max(best, row[x]);
  return best;
}

namespace {

// How many of the steps i = 0, 1, ... keep coordinate c0 + i * dir (dir = +1 or -1) in
// [0, size): all steps up to the first outside.
inline std::int64_t steps_inside(int c0, int dir, int size) {
  if (c0 < 0 || c0 >= size) return 0;
  return dir > 0 ? size - c0 : c0 + 1;
}

// The same for the 16.16 fixed-point coordinate (f0 + i * df) >> 16 in [0, size): exact
// integer arithmetic, so the count is the loop's own first exit. Only the first `needed` steps
// matter: when the last of them is inside, so are all before it (the coordinate is monotonic),
// and the answer is needed without the division (a fifth of a short ray's set-up).
inline std::int64_t fixed_steps_inside(std::int64_t f0, std::int64_t df, int size,
                                       std::int64_t needed) {
  const std::int64_t end = static_cast<std::int64_t>(size) << 16;
  if (f0 < 0 || f0 >= end) return 0;
  if (const std::int64_t last = f0 + (needed - 1) * df; last >= 0 && last < end) return needed;
  if (df > 0) return (end - f0 + df - 1) / df;
  if (df < 0) return f0 / -df + 1;
  return std::numeric_limits<std::int64_t>::max();
}

// One vote in each of count cells from p on, moving by major_stride per step and by minor_stride
// per unit of the fixed-point minor coordinate; with Saturate a full cell stays full, without a
// branch.
template <bool Saturate>
inline void add_votes(std::uint16_t* p, std::ptrdiff_t major_stride, std::ptrdiff_t minor_stride,
                      std::int64_t minor_fp, std::int64_t dminor, std::int64_t count) {
  auto vote = [&] {
    std::uint16_t& cell = p[(minor_fp >> 16) * minor_stride];
    if constexpr (Saturate)
      cell = static_cast<std::uint16_t>(cell + (cell != 0xFFFF));
    else
      ++cell;
    p += major_stride;
    minor_fp += dminor;
  };
  // Four cells a turn (the same cells in the same order): the loop's own test and jump were a
  // fifth of a cell's work.
  std::int64_t i = 0;
  for (; i + 4 <= count; i += 4) {
    vote();
    vote();
    vote();
    vote();
  }
  for (; i < count; ++i) vote();
}

}  // namespace

RayDirection ray_direction(double dir_x, double dir_y) {
  RayDirection d;
  // Not std::hypot: no overflow to guard against here, and it is several times slower.
  const double norm = std::sqrt(dir_x * dir_x + dir_y * dir_y);
  if (norm <= 0.0) return d;
  d.plottable = true;
  d.ux = dir_x / norm;
  d.uy = dir_y / norm;
  d.x_major = std::abs(d.ux) >= std::abs(d.uy);
  const double major = d.x_major ? d.ux : d.uy;
  d.abs_major = std::abs(major);
  d.step = major > 0 ? 1 : -1;
  d.slope = (d.x_major ? d.uy : d.ux) / d.abs_major;
  d.dminor = round_half_away(d.slope * 65536.0);
  return d;
}

std::int64_t plot_ray(cv::Mat& accumulator, double start_x, double start_y, double dir_x,
                      double dir_y, double t0_px, double t1_px, bool saturate) {
  return plot_ray(accumulator, start_x, start_y, ray_direction(dir_x, dir_y), t0_px, t1_px,
                  saturate);
}

std::int64_t plot_ray(cv::Mat& accumulator, double start_x, double start_y, const RayDirection& dir,
                      double t0_px, double t1_px, bool saturate) {
  if (!dir.plottable || t1_px < t0_px) return 0;
  const bool x_major = dir.x_major;
  const int step = dir.step;
  const double slope = dir.slope;
  const std::int64_t dminor = dir.dminor;
  const double sx = start_x + dir.ux * t0_px;
  const double sy = start_y + dir.uy * t0_px;
  const int steps = static_cast<int>((t1_px - t0_px) * dir.abs_major);
  // Minor coordinate in 16.16 fixed point: integer stepping, no per-cell rounding.
  const int m = static_cast<int>(round_half_away(x_major ? sx : sy));
  const double minor0 = (x_major ? sy : sx) + (m - (x_major ? sx : sy)) * slope * step;
  const std::int64_t minor_fp = round_half_away((minor0 + 0.5) * 65536.0);
  const int w = accumulator.cols;
  const int h = accumulator.rows;
  // A ray leaves the image once and never comes back (both coordinates are monotonic): the
  // cells plotted are the steps before the first one outside, counted up front so that the
  // loop has no bounds test.
  const std::int64_t needed = static_cast<std::int64_t>(steps) + 1;
  const std::int64_t count =
      std::min({needed, steps_inside(m, step, x_major ? w : h),
                fixed_steps_inside(minor_fp, dminor, x_major ? h : w, needed)});
  if (count <= 0) return 0;
  // Cells per row: a CV_16U map's row step in bytes over 2 (step1() is a library call per ray).
  const auto stride = static_cast<std::ptrdiff_t>(accumulator.step[0] / sizeof(std::uint16_t));
  auto* data = accumulator.ptr<std::uint16_t>(0);
  std::uint16_t* const first = x_major ? data + m : data + static_cast<std::ptrdiff_t>(m) * stride;
  const std::ptrdiff_t major_stride = x_major ? step : step * stride;
  const std::ptrdiff_t minor_stride = x_major ? stride : 1;
  if (saturate)
    add_votes<true>(first, major_stride, minor_stride, minor_fp, dminor, count);
  else
    add_votes<false>(first, major_stride, minor_stride, minor_fp, dminor, count);
  return count;
}

namespace {

// One flag per column of row (1 <= x < w - 1), computed without branches so the compiler
// vectorises it (a textured image leaves much of the map above the floor, where branches
// mispredict). Strict against earlier neighbours, non-strict against later: one pixel per
// plateau.
template <typename T>
[[gnu::always_inline]] inline void flag_maxima(const T* __restrict up, const T* __restrict row,
                                               const T* __restrict down, int w, T min_value,
                                               std::uint8_t* __restrict flag) {
  for (int x = 1; x < w - 1; ++x) {
    const T v = row[x];
    flag[x] = (v >= min_value) & (v > up[x - 1]) & (v > up[x]) & (v > up[x + 1]) &
              (v > row[x - 1]) & (v >= row[x + 1]) & (v >= down[x - 1]) & (v >= down[x]) &
              (v >= down[x + 1]);
  }
}

// The smoothed vote maps are integer: their copy gets the CPU's widest vectors.
SB_AVX2_CLONE void flag_row_maxima(const int* up, const int* row, const int* down, int w,
                                   int min_value, std::uint8_t* flag) {
  flag_maxima(up, row, down, w, min_value, flag);
}

void flag_row_maxima(const float* up, const float* row, const float* down, int w, float min_value,
                     std::uint8_t* flag) {
  flag_maxima(up, row, down, w, min_value, flag);
}

// Whether some value of the row reaches min_value: most rows of a plain scene's map do not,
// and testing that is a fifth of the cost of flagging them.
bool row_reaches(const int* row, int w, int min_value) {
  return row_maximum(row, w) >= min_value;
}

bool row_reaches(const float* row, int w, float min_value) {
  return w > 0 && *std::max_element(row, row + w) >= min_value;
}

// flag_maxima's test of one column (1 <= x < w - 1).
inline bool is_row_maximum(const int* up, const int* row, const int* down, int x, int min_value) {
  const int v = row[x];
  return v >= min_value && v > up[x - 1] && v > up[x] && v > up[x + 1] && v > row[x - 1] &&
         v >= row[x + 1] && v >= down[x - 1] && v >= down[x] && v >= down[x + 1];
}

#if SB_HAVE_AVX2_KERNELS
SB_TARGET_AVX2 inline __m256i load8(const int* p) {
  return _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p));
}

// local_maxima's int rows eight columns at a time: v above the largest earlier neighbour and at
// least the largest later one (the same integer tests as flag_maxima, fewer compares), the
// passing columns a bit mask whose set bits are pushed in column order; no byte flags to scan.
SB_TARGET_AVX2 void push_row_maxima_avx2(const int* up, const int* row, const int* down, int w,
                                         int min_value, int y, std::vector<Peak>& out) {
  const __m256i floor_v = _mm256_set1_epi32(min_value);
  int x = 1;
  for (; x + 8 <= w - 1; x += 8) {
    const __m256i v = load8(row + x);
    const __m256i earlier =
        _mm256_max_epi32(_mm256_max_epi32(load8(up + x - 1), load8(up + x)),
                         _mm256_max_epi32(load8(up + x + 1), load8(row + x - 1)));
    const __m256i later =
        _mm256_max_epi32(_mm256_max_epi32(load8(row + x + 1), load8(down + x - 1)),
                         _mm256_max_epi32(load8(down + x), load8(down + x + 1)));
    const __m256i fail =
        _mm256_or_si256(_mm256_cmpgt_epi32(later, v), _mm256_cmpgt_epi32(floor_v, v));
    const __m256i pass = _mm256_andnot_si256(fail, _mm256_cmpgt_epi32(v, earlier));
    for (auto mask = static_cast<unsigned>(_mm256_movemask_ps(_mm256_castsi256_ps(pass)));
         mask != 0; mask &= mask - 1) {
      const int xi = x + std::countr_zero(mask);
      out.push_back({xi, y, static_cast<float>(row[xi])});
    }
  }
  for (; x < w - 1; ++x)
    if (is_row_maximum(up, row, down, x, min_value))
      out.push_back({x, y, static_cast<float>(row[x])});
}
#endif

// row_maxima: the rows' largest values when known (one per row), else empty.
template <typename T>
void local_maxima(const cv::Mat& m, T min_value, std::span<const int> row_maxima,
                  std::vector<Peak>& out) {
  std::vector<std::uint8_t> flag(static_cast<size_t>(m.cols) + 8, 0);
  for (int y = 1; y < m.rows - 1; ++y) {
    const T* up = m.ptr<T>(y - 1);
    const T* row = m.ptr<T>(y);
    const T* down = m.ptr<T>(y + 1);
    if (row_maxima.empty() ? !row_reaches(row, m.cols, min_value)
                           : row_maxima[static_cast<std::size_t>(y)] < min_value)
      continue;
#if SB_HAVE_AVX2_KERNELS
    if constexpr (std::is_same_v<T, int>) {
      if (cpu_has_avx2()) {
        push_row_maxima_avx2(up, row, down, m.cols, min_value, y, out);
        continue;
      }
    }
#endif
    flag_row_maxima(up, row, down, m.cols, min_value, flag.data());
    for (int x = 1; x < m.cols - 1; x += 8) {
      std::uint64_t eight;
      std::memcpy(&eight, flag.data() + x, 8);
      for (; eight != 0; eight &= eight - 1) {
        const int xi = x + std::countr_zero(eight) / 8;
        if (xi < m.cols - 1) out.push_back({xi, y, static_cast<float>(row[xi])});
      }
    }
  }
}

}  // namespace

std::vector<Peak> find_peaks(const cv::Mat& smoothed, float min_value, double min_separation_px,
                             int max_peaks) {
  return find_peaks(smoothed, min_value, min_separation_px, max_peaks, {});
}

std::vector<Peak> find_peaks(const cv::Mat& smoothed, float min_value, double min_separation_px,
                             int max_peaks, std::span<const int> row_maxima) {
  std::vector<Peak> candidates;
  const bool known =
      smoothed.type() == CV_32S && row_maxima.size() == static_cast<std::size_t>(smoothed.rows);
  if (smoothed.type() == CV_32S)
    local_maxima<int>(smoothed, static_cast<int>(std::ceil(min_value)),
                      known ? row_maxima : std::span<const int>{}, candidates);
  else
    local_maxima<float>(smoothed, min_value, {}, candidates);
  // Strongest first, raster order among equals (candidates are in raster order): a heap pops
  // them in that order, and only as many as it takes to keep max_peaks (a textured image has
  // thousands of candidates; sorting them all cost more than the rest of this function).
  std::vector<std::pair<Peak, std::size_t>> heap;
  heap.reserve(candidates.size());
  for (std::size_t i = 0; i < candidates.size(); ++i) heap.emplace_back(candidates[i], i);
  const auto weaker = [](const std::pair<Peak, std::size_t>& a,
                         const std::pair<Peak, std::size_t>& b) {
    return a.first.value != b.first.value ? a.first.value < b.first.value : a.second > b.second;
  };
  std::make_heap(heap.begin(), heap.end(), weaker);
  std::vector<Peak> kept;
  const double min_d2 = min_separation_px * min_separation_px;
  while (!heap.empty() && static_cast<int>(kept.size()) < max_peaks) {
    std::pop_heap(heap.begin(), heap.end(), weaker);
    const Peak c = heap.back().first;
    heap.pop_back();
    const bool close = std::any_of(kept.begin(), kept.end(), [&](const Peak& k) {
      const double dx = k.x - c.x, dy = k.y - c.y;
      return dx * dx + dy * dy < min_d2;
    });
    if (!close) kept.push_back(c);
  }
  return kept;
}

double peak_to_mean(const cv::Mat& smoothed) {
  double max_v = 0.0;
  cv::minMaxLoc(smoothed, nullptr, &max_v);
  const double mean = cv::mean(smoothed)[0];
  return mean > 0.0 ? max_v / mean : 0.0;
}

}  // namespace stereoball::ball_detector
