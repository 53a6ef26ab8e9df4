#include "ball_detector/core/canny.hpp"

#include "ball_detector/core/cpu_dispatch.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

#if SB_HAVE_AVX2_KERNELS
#include <immintrin.h>
#endif

namespace stereoball::ball_detector {
namespace {

constexpr std::uint8_t kWeak = 0;
constexpr std::uint8_t kNone = 1;
constexpr std::uint8_t kEdge = 2;

// tan(22.5 deg) in 15-bit fixed point: the sector boundaries of the gradient direction.
constexpr int kTan22Q15 = 13573;

// Codes of columns [x, w) of one row from its gradients and the magnitudes of it and its two
// neighbour rows (each readable at [-1, w]). Written with masks only (no branches, no bool
// selects) so that the compiler vectorises the loop; each mask is 0 or all ones.
SB_AVX2_CLONE void classify_row(const short* __restrict dx, const short* __restrict dy,
                                const std::int16_t* __restrict up,
                                const std::int16_t* __restrict mid,
                                const std::int16_t* __restrict down, int x, int w, int low,
                                int high, std::uint8_t* __restrict codes) {
  for (; x < w; ++x) {
    const int m = mid[x];
    const int gx = dx[x], gy = dy[x];
    const int ax = gx < 0 ? -gx : gx;
    const int ay_q15 = (gy < 0 ? -gy : gy) << 15;
    const int tan22_ax = ax * kTan22Q15;
    const int tan67_ax = tan22_ax + (ax << 16);  // tan(67.5) = tan(22.5) + 2
    const int horizontal = -(ay_q15 < tan22_ax);
    const int vertical = ~horizontal & -(ay_q15 > tan67_ax);
    const int diagonal = ~(horizontal | vertical);
    const int opposite_signs = (gx ^ gy) >> 31;
    // One side strict, the other not, so a plateau two pixels wide keeps exactly one.
    const int max_h = -((m > mid[x - 1]) & (m >= mid[x + 1]));
    const int max_v = -((m > up[x]) & (m >= down[x]));
    const int max_main_diag = -((m > up[x - 1]) & (m > down[x + 1]));
    const int max_anti_diag = -((m > up[x + 1]) & (m > down[x - 1]));
    const int max_d = (opposite_signs & max_anti_diag) | (~opposite_signs & max_main_diag);
    const int candidate =
        -(m > low) & ((horizontal & max_h) | (vertical & max_v) | (diagonal & max_d));
    const int strong = -(m > high);
    codes[x] = static_cast<std::uint8_t>((candidate & strong & kEdge) | (~candidate & kNone));
  }
}

#if SB_HAVE_AVX2_KERNELS
// Sixteen 16-bit values from p.
SB_TARGET_AVX2 inline __m256i load_16(const std::int16_t* p) {
  return _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p));
}

// classify_row for the sixteen pixels from column x in 16-bit lanes (|dx|, |dy| < 2^14, so
// magnitudes < 2^15), twice the pixels per instruction of the 32-bit loop. The sector tests
// without 32-bit products: with hi:lo the 32-bit product ax * 2 * kTan22Q15 (hi = floor(ax *
// kTan22Q15 / 2^15), lo = twice the remainder), ay * 2^15 < ax * kTan22Q15 is ay < hi or (ay ==
// hi and lo != 0), and ay * 2^15 > ax * kTan22Q15 + ax * 2^16 is ay - 2 * ax > hi.
SB_TARGET_AVX2 inline void classify_16(const short* dx, const short* dy, const std::int16_t* up,
                                       const std::int16_t* mid, const std::int16_t* down, int x,
                                       const __m256i& low, const __m256i& high, __m256i& codes) {
  const __m256i gx = load_16(dx + x), gy = load_16(dy + x);
  const __m256i ax = _mm256_abs_epi16(gx), ay = _mm256_abs_epi16(gy);
  const __m256i tan22x2 = _mm256_set1_epi16(2 * kTan22Q15);
  const __m256i hi = _mm256_mulhi_epu16(ax, tan22x2), lo = _mm256_mullo_epi16(ax, tan22x2);
  const __m256i zero = _mm256_setzero_si256();
  const __m256i horizontal = _mm256_or_si256(
      _mm256_cmpgt_epi16(hi, ay),
      _mm256_andnot_si256(_mm256_cmpeq_epi16(lo, zero), _mm256_cmpeq_epi16(ay, hi)));
  const __m256i vertical = _mm256_andnot_si256(
      horizontal, _mm256_cmpgt_epi16(_mm256_sub_epi16(ay, _mm256_add_epi16(ax, ax)), hi));
  const __m256i opposite_signs = _mm256_srai_epi16(_mm256_xor_si256(gx, gy), 15);
  const __m256i m = load_16(mid + x);
  const __m256i max_h = _mm256_andnot_si256(_mm256_cmpgt_epi16(load_16(mid + x + 1), m),
                                            _mm256_cmpgt_epi16(m, load_16(mid + x - 1)));
  const __m256i max_v = _mm256_andnot_si256(_mm256_cmpgt_epi16(load_16(down + x), m),
                                            _mm256_cmpgt_epi16(m, load_16(up + x)));
  const __m256i max_main_diag = _mm256_and_si256(_mm256_cmpgt_epi16(m, load_16(up + x - 1)),
                                                 _mm256_cmpgt_epi16(m, load_16(down + x + 1)));
  const __m256i max_anti_diag = _mm256_and_si256(_mm256_cmpgt_epi16(m, load_16(up + x + 1)),
                                                 _mm256_cmpgt_epi16(m, load_16(down + x - 1)));
  const __m256i max_d = _mm256_blendv_epi8(max_main_diag, max_anti_diag, opposite_signs);
  const __m256i across = _mm256_or_si256(
      _mm256_or_si256(_mm256_and_si256(horizontal, max_h), _mm256_and_si256(vertical, max_v)),
      _mm256_andnot_si256(_mm256_or_si256(horizontal, vertical), max_d));
  const __m256i candidate = _mm256_and_si256(_mm256_cmpgt_epi16(m, low), across);
  const __m256i edge = _mm256_and_si256(_mm256_and_si256(candidate, _mm256_cmpgt_epi16(m, high)),
                                        _mm256_set1_epi16(kEdge));
  codes = _mm256_or_si256(edge, _mm256_andnot_si256(candidate, _mm256_set1_epi16(kNone)));
}

// classify_row with AVX2, thirty-two pixels per step (rows narrower than that: the plain loop).
// The thresholds are clamped to 16 bits without changing a test: magnitudes lie in [0, 32766].
SB_TARGET_AVX2 void classify_row_avx2(const short* dx, const short* dy, const std::int16_t* up,
                                      const std::int16_t* mid, const std::int16_t* down, int w,
                                      int low, int high, std::uint8_t* codes) {
  const __m256i low16 = _mm256_set1_epi16(static_cast<short>(std::clamp(low, -1, 32767)));
  const __m256i high16 = _mm256_set1_epi16(static_cast<short>(std::clamp(high, -1, 32767)));
  if (w < 32) {
    classify_row(dx, dy, up, mid, down, 0, w, low, high, codes);
    return;
  }
  // The last step ends at the row's end, overlapping the one before (it writes the same codes).
  for (int x = 0;; x = std::min(x + 32, w - 32)) {
    __m256i a, b;
    classify_16(dx, dy, up, mid, down, x, low16, high16, a);
    classify_16(dx, dy, up, mid, down, x + 16, low16, high16, b);
    // packus interleaves the 128-bit halves; the permute puts the 32 codes back in order.
    const __m256i bytes = _mm256_permute4x64_epi64(_mm256_packus_epi16(a, b), 0xD8);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(codes + x), bytes);
    if (x == w - 32) break;
  }
}
#endif

// Codes of one row (see classify_row), with AVX2 where the CPU has it unless plain.
void classify(const short* dx, const short* dy, const std::int16_t* up, const std::int16_t* mid,
              const std::int16_t* down, int w, int low, int high, bool plain, std::uint8_t* codes) {
#if SB_HAVE_AVX2_KERNELS
  if (!plain && cpu_has_avx2()) {
    classify_row_avx2(dx, dy, up, mid, down, w, low, high, codes);
    return;
  }
#endif
  classify_row(dx, dy, up, mid, down, 0, w, low, high, codes);
}

// |dx| + |dy| < 2^15 (canny_l1's precondition) in 16 bits.
SB_AVX2_CLONE void l1_magnitudes(const short* __restrict gx, const short* __restrict gy, int w,
                                 std::int16_t* __restrict out) {
  for (int x = 0; x < w; ++x) out[x] = static_cast<std::int16_t>(std::abs(gx[x]) + std::abs(gy[x]));
}

void magnitudes_of_row(const cv::Mat& dx, const cv::Mat& dy, int y, std::int16_t* out) {
  l1_magnitudes(dx.ptr<short>(y), dy.ptr<short>(y), dx.cols, out);
}

SB_AVX2_CLONE void codes_to_edges(const std::uint8_t* __restrict codes, int w,
                                  std::uint8_t* __restrict out) {
  for (int x = 0; x < w; ++x) out[x] = codes[x] == kEdge ? 255 : 0;
}

// Pushes the edge pixels of a row of codes (eight at a time: kEdge is the only code with
// bit 1 set).
void push_edges(std::uint8_t* codes, int w, std::vector<std::uint8_t*>& stack) {
  for (int x = 0; x < w; x += 8) {
    std::uint64_t eight;
    std::memcpy(&eight, codes + x, 8);
    for (eight &= 0x0202020202020202ull; eight != 0; eight &= eight - 1) {
      const int xi = x + std::countr_zero(eight) / 8;
      if (xi < w) stack.push_back(codes + xi);
    }
  }
}

#if SB_HAVE_AVX2_KERNELS
// push_edges thirty-two codes per step (one compare and a byte mask); the plain loop does the
// rest of the row.
SB_TARGET_AVX2 void push_edges_avx2(std::uint8_t* codes, int w, std::vector<std::uint8_t*>& stack) {
  const __m256i edge = _mm256_set1_epi8(static_cast<char>(kEdge));
  int x = 0;
  for (; x + 32 <= w; x += 32) {
    const __m256i c = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(codes + x));
    for (auto mask = static_cast<std::uint32_t>(_mm256_movemask_epi8(_mm256_cmpeq_epi8(c, edge)));
         mask != 0; mask &= mask - 1)
      stack.push_back(codes + x + std::countr_zero(mask));
  }
  push_edges(codes + x, w - x, stack);
}
#endif

// Pushes the edge pixels of a row of codes, with AVX2 where the CPU has it unless plain.
void push_row_edges(std::uint8_t* codes, int w, bool plain, std::vector<std::uint8_t*>& stack) {
#if SB_HAVE_AVX2_KERNELS
  if (!plain && cpu_has_avx2()) {
    push_edges_avx2(codes, w, stack);
    return;
  }
#endif
  push_edges(codes, w, stack);
}

// Hysteresis: every weak candidate 8-connected to an edge becomes one. The eight neighbours
// are tested one by one, unrolled: most are not weak, and each then costs a compare.
void grow_edges(std::ptrdiff_t stride, std::vector<std::uint8_t*>& stack) {
  const auto visit = [&stack](std::uint8_t* q) {
    if (*q == kWeak) {
      *q = kEdge;
      stack.push_back(q);
    }
  };
  while (!stack.empty()) {
    std::uint8_t* p = stack.back();
    stack.pop_back();
    std::uint8_t* up = p - stride;
    std::uint8_t* down = p + stride;
    visit(p - 1);
    visit(p + 1);
    visit(up - 1);
    visit(up);
    visit(up + 1);
    visit(down - 1);
    visit(down);
    visit(down + 1);
  }
}

}  // namespace

void canny_l1(const cv::Mat& dx, const cv::Mat& dy, double low, double high, cv::Mat& edges,
              CannyWorkspace& work) {
  CV_Assert(dx.type() == CV_16SC1 && dy.type() == CV_16SC1 && dx.size() == dy.size());
  if (low > high) std::swap(low, high);
  const int h = dx.rows, w = dx.cols;
  const int low_i = cvFloor(low), high_i = cvFloor(high);
  const std::ptrdiff_t stride = w + 2;
  // Border of kNone (never an edge, never grown into): the rows above and below the image
  // here, each row's two ends in the loop (classify writes the rest, so the buffer is not
  // cleared whole); +8 so eight-byte reads stay inside.
  work.codes.resize(static_cast<size_t>(stride) * (h + 2) + 8);
  std::memset(work.codes.data(), kNone, static_cast<size_t>(stride));
  std::memset(work.codes.data() + (h + 1) * stride, kNone, static_cast<size_t>(stride) + 8);
  work.magnitudes.assign(3 * static_cast<size_t>(stride), 0);
  work.stack.clear();
  std::int16_t* rows[3] = {work.magnitudes.data() + 1, work.magnitudes.data() + stride + 1,
                           work.magnitudes.data() + 2 * stride + 1};
  if (h > 0) magnitudes_of_row(dx, dy, 0, rows[1]);
  for (int y = 0; y < h; ++y) {
    // Rolling window of magnitude rows: above, this one, below (zero outside the image).
    if (y + 1 < h)
      magnitudes_of_row(dx, dy, y + 1, rows[2]);
    else
      std::fill(rows[2] - 1, rows[2] + w + 1, 0);
    std::uint8_t* codes = work.codes.data() + (y + 1) * stride + 1;
    codes[-1] = codes[w] = kNone;
    classify(dx.ptr<short>(y), dy.ptr<short>(y), rows[0], rows[1], rows[2], w, low_i, high_i,
             work.plain, codes);
    push_row_edges(codes, w, work.plain, work.stack);
    std::rotate(rows, rows + 1, rows + 3);
  }
  grow_edges(stride, work.stack);
  edges.create(h, w, CV_8UC1);
  for (int y = 0; y < h; ++y) {
    const std::uint8_t* codes = work.codes.data() + (y + 1) * stride + 1;
    codes_to_edges(codes, w, edges.ptr<std::uint8_t>(y));
  }
}

}  // namespace stereoball::ball_detector
