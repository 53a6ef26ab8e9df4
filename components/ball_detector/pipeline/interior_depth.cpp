#include "ball_detector/pipeline/interior_depth.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace stereoball::ball_detector {
namespace {

// The square inside the outline, half side 0.55 r: its corners (0.78 r from the centre) stay
// clear of the rim, whose pixels mix the ball with what is behind it.
constexpr double kHalfSidePerRadius = 0.55;
// Rows matched: enough texture for a clear correlation peak at any radius, and a bounded cost
// (about 12 x 2 x 0.55 r x shifts products) for the largest circles.
constexpr int kMaxRows = 12;
constexpr int kMinWidthPx = 8;
// Real rigs rectify to within a pixel: each row is matched one row up and down as well.
constexpr int kRowSlackPx = 1;
// Shifts this close to the ball's own range count as the ball's (sub-pixel outline, rounding).
constexpr double kBallSlackPx = 1.5;
// Fewer textured rows than this: too little to judge, the pair stands.
constexpr int kMinRowsTextured = 3;

double mean_std(const cv::Mat& m) {
  cv::Scalar mean, sd;
  cv::meanStdDev(m, mean, sd);
  double sum = 0.0;
  for (int c = 0; c < m.channels(); ++c) sum += sd[c];
  return sum / m.channels();
}

std::vector<int> sample_rows(const cv::Rect& region) {
  const int top = region.y + kRowSlackPx, bottom = region.y + region.height - 1 - kRowSlackPx;
  std::vector<int> rows;
  if (bottom < top) return rows;
  const int n = std::min(kMaxRows, bottom - top + 1);
  for (int i = 0; i < n; ++i) rows.push_back(n == 1 ? top : top + i * (bottom - top) / (n - 1));
  return rows;
}


}  // namespace

cv::Rect interior_rows_region(const Circle& circle, cv::Size size) {
  const double h = kHalfSidePerRadius * circle.radius_px;
  if (!(h > 0.0) || !std::isfinite(circle.x_px) || !std::isfinite(circle.y_px)) return {};
  const cv::Point tl(static_cast<int>(std::ceil(circle.x_px - h)),
                     static_cast<int>(std::ceil(circle.y_px - h)) - kRowSlackPx);
  const cv::Point br(static_cast<int>(std::floor(circle.x_px + h)) + 1,
                     static_cast<int>(std::floor(circle.y_px + h)) + 1 + kRowSlackPx);
  const cv::Rect region = cv::Rect(tl, br) & cv::Rect(cv::Point(0, 0), size);
  if (region.width < kMinWidthPx || region.height < 1 + 2 * kRowSlackPx) return {};
  return region;
}

cv::Rect interior_search_region(const cv::Rect& left_region, const ShiftWindow& window,
                                cv::Size size) {
  if (left_region.empty()) return {};
  const int lo = static_cast<int>(std::floor(window.search_lo_px));
  const int hi = static_cast<int>(std::ceil(window.search_hi_px));
  const cv::Rect wanted(cv::Point(left_region.x - hi, left_region.y),
                        cv::Point(left_region.br().x - lo, left_region.br().y));
  return wanted & cv::Rect(cv::Point(0, 0), size);
}

namespace {

struct RowMatch {
  bool textured = false;
  double best_shift_px = 0.0, best_match = -1.0, ball_match = -1.0;
};

// One row of the inside against the same row of the right eye (+-kRowSlackPx) at every shift
// in [s_lo, s_hi]: each row on its own, because a floor seen by a level rig has one disparity
// per row and a different one on the next (a joint template over a slanted floor matches
// nowhere).
RowMatch match_row(const cv::Mat& left, const cv::Mat& right, int y, const cv::Rect& region,
                   int s_lo, int s_hi, const ShiftWindow& window, const InteriorDepthParams& p,
                   std::vector<float>& match) {
  RowMatch out;
  const cv::Mat templ = left(cv::Rect(region.x, y, region.width, 1));
  if (mean_std(templ) < p.min_texture) return out;
  out.textured = true;
  match.assign(static_cast<std::size_t>(s_hi - s_lo + 1), -1.0f);
  cv::Mat result;
  const int strip_x = region.x - s_hi, strip_width = region.width + (s_hi - s_lo);
  for (int dy = -kRowSlackPx; dy <= kRowSlackPx; ++dy) {
    const int yr = std::clamp(y + dy, 0, right.rows - 1);
    cv::matchTemplate(right(cv::Rect(strip_x, yr, strip_width, 1)), templ, result,
                      cv::TM_CCOEFF_NORMED);
    // result column j: the row at strip_x + j in the right eye, i.e. shift s_hi - j.
    for (int j = 0; j < result.cols; ++j) {
      float& m = match[static_cast<std::size_t>(s_hi - j - s_lo)];
      m = std::max(m, result.at<float>(0, j));
    }
  }
  for (int s = s_lo; s <= s_hi; ++s) {
    const double m = match[static_cast<std::size_t>(s - s_lo)];
    if (m > out.best_match) {
      out.best_match = m;
      out.best_shift_px = s;
    }
    if (s >= window.ball_lo_px - kBallSlackPx && s <= window.ball_hi_px + kBallSlackPx)
      out.ball_match = std::max(out.ball_match, m);
  }
  return out;
}

bool row_elsewhere(const RowMatch& r, const ShiftWindow& window, const InteriorDepthParams& p) {
  const bool outside = r.best_shift_px < window.ball_lo_px - kBallSlackPx ||
                       r.best_shift_px > window.ball_hi_px + kBallSlackPx;
  return outside && r.best_match >= p.min_match && r.best_match - r.ball_match >= p.min_margin;
}

}  // namespace

InteriorDepth interior_depth(const cv::Mat& left, const cv::Mat& right, const Circle& circle,
                             const ShiftWindow& window, const InteriorDepthParams& params) {
  InteriorDepth out;
  if (left.empty() || left.type() != right.type() || left.size() != right.size() ||
      left.depth() != CV_8U)
    return out;
  const cv::Rect region = interior_rows_region(circle, left.size());
  const std::vector<int> rows = sample_rows(region);
  if (rows.empty()) return out;
  // Whole shifts s keep the row's columns [x - s, x + width - s) inside the right image.
  const int s_lo = std::max(static_cast<int>(std::ceil(window.search_lo_px)),
                            region.br().x - right.cols);
  const int s_hi = std::min(static_cast<int>(std::floor(window.search_hi_px)), region.x);
  if (s_hi < s_lo) return out;
  std::vector<float> match;
  std::vector<RowMatch> elsewhere;
  for (const int y : rows) {
    const RowMatch r = match_row(left, right, y, region, s_lo, s_hi, window, params, match);
    if (!r.textured) continue;
    ++out.rows_textured;
    if (row_elsewhere(r, window, params)) elsewhere.push_back(r);
  }
  out.textured = out.rows_textured >= kMinRowsTextured;
  out.rows_elsewhere = static_cast<int>(elsewhere.size());
  if (elsewhere.empty()) return out;
  // The reason quotes the median row that lies elsewhere.
  std::nth_element(elsewhere.begin(), elsewhere.begin() + elsewhere.size() / 2, elsewhere.end(),
                   [](const RowMatch& a, const RowMatch& b) {
                     return a.best_shift_px < b.best_shift_px;
                   });
  const RowMatch& median = elsewhere[elsewhere.size() / 2];
  out.best_shift_px = median.best_shift_px;
  out.best_match = median.best_match;
  out.ball_match = median.ball_match;
  // Most textured rows must agree: one row may match a repeated pattern by chance.
  out.contradicts = out.textured && 2 * out.rows_elsewhere > out.rows_textured;
  return out;
}

}  // namespace stereoball::ball_detector
