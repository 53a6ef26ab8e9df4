#include "ball_detector/core/canny.hpp"

#include "ball_detector/core/cpu_dispatch.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

namespace stereoball::ball_detector {
namespace {

constexpr std::uint8_t kWeak = 0;
constexpr std::uint8_t kNone = 1;
constexpr std::uint8_t kEdge = 2;

// tan(22.5 deg) in 15-bit fixed point: the sector boundaries of the gradient direction.
constexpr int kTan22Q15 = 13573;

// Codes of one row from its gradients and the magnitudes of it and its two neighbour rows
// (each readable at [-1, w]). Written with masks only (no branches, no bool selects) so that
// the compiler vectorises the loop; each mask is 0 or all ones.
SB_AVX2_CLONE void classify_row(const short* __restrict dx, const short* __restrict dy,
                                const int* __restrict up, const int* __restrict mid,
                                const int* __restrict down, int w, int low, int high,
                                std::uint8_t* __restrict codes) {
  for (int x = 0; x < w; ++x) {
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

SB_AVX2_CLONE void l1_magnitudes(const short* __restrict gx, const short* __restrict gy, int w,
                                 int* __restrict out) {
  for (int x = 0; x < w; ++x) out[x] = std::abs(gx[x]) + std::abs(gy[x]);
}

void magnitudes_of_row(const cv::Mat& dx, const cv::Mat& dy, int y, int* out) {
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

// Hysteresis: every weak candidate 8-connected to an edge becomes one.
void grow_edges(std::ptrdiff_t stride, std::vector<std::uint8_t*>& stack) {
  const std::ptrdiff_t offsets[8] = {-1,          1,          -stride - 1, -stride,
                                     -stride + 1, stride - 1, stride,      stride + 1};
  while (!stack.empty()) {
    std::uint8_t* p = stack.back();
    stack.pop_back();
    for (const std::ptrdiff_t o : offsets) {
      if (p[o] == kWeak) {
        p[o] = kEdge;
        stack.push_back(p + o);
      }
    }
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
  // Border of kNone (never an edge, never grown into); +8 so eight-byte reads stay inside.
  work.codes.assign(static_cast<size_t>(stride) * (h + 2) + 8, kNone);
  work.magnitudes.assign(3 * static_cast<size_t>(stride), 0);
  work.stack.clear();
  int* rows[3] = {work.magnitudes.data() + 1, work.magnitudes.data() + stride + 1,
                  work.magnitudes.data() + 2 * stride + 1};
  if (h > 0) magnitudes_of_row(dx, dy, 0, rows[1]);
  for (int y = 0; y < h; ++y) {
    // Rolling window of magnitude rows: above, this one, below (zero outside the image).
    if (y + 1 < h)
      magnitudes_of_row(dx, dy, y + 1, rows[2]);
    else
      std::fill(rows[2] - 1, rows[2] + w + 1, 0);
    std::uint8_t* codes = work.codes.data() + (y + 1) * stride + 1;
    classify_row(dx.ptr<short>(y), dy.ptr<short>(y), rows[0], rows[1], rows[2], w, low_i, high_i,
                 codes);
    push_edges(codes, w, work.stack);
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
