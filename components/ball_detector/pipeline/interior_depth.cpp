#include "ball_detector/pipeline/interior_depth.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace stereoball::ball_detector {
namespace {

// The disc inside the outline, 0.8 r: the rim's pixels mix the ball with what is behind it.
// Its front part is the ball's surface between its centre's depth and its nearest point.
constexpr double kInsidePerRadius = 0.8;
// Rows matched: enough texture for a clear correlation peak at any radius, and a bounded cost
// (about 12 x 3 x 1.6 r x shifts products) for the largest circles.
constexpr int kMaxRows = 12;
constexpr int kMinWidthPx = 8;
// A row cut to what the right eye sees keeps at least this many pixels (a few texture blobs).
constexpr int kMinCutWidthPx = 24;
// Above this many products per row (rows x positions x template values) the correlation goes
// through matchTemplate's DFT (a close ball's wide rows over hundreds of shifts).
constexpr std::int64_t kDirectCorrelationMaxProducts = 200'000;
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

// One sampled row of the inside: columns [x, x + width) of row y.
struct RowSpan {
  int y = 0, x = 0, width = 0;
};

// Up to kMaxRows rows evenly over the part of the inside disc in the image (one row of slack
// from the top and bottom borders), each the disc's chord there clipped to the image. A circle
// whose centre is below the image (a chance circle on close carpet, a ball passing under the
// camera) is judged on the part of its inside that shows.
std::vector<RowSpan> interior_spans(const Circle& circle, cv::Size size) {
  std::vector<RowSpan> spans;
  const double reach = kInsidePerRadius * circle.radius_px;
  if (!(reach > 0.0) || !std::isfinite(circle.x_px) || !std::isfinite(circle.y_px) ||
      !std::isfinite(reach))
    return spans;
  const double top_d = std::max(std::ceil(circle.y_px - reach), double{kRowSlackPx});
  const double bottom_d =
      std::min(std::floor(circle.y_px + reach), static_cast<double>(size.height - 1 - kRowSlackPx));
  if (bottom_d < top_d) return spans;
  const int top = static_cast<int>(top_d), bottom = static_cast<int>(bottom_d);
  const int n = std::min(kMaxRows, bottom - top + 1);
  for (int i = 0; i < n; ++i) {
    const int y = n == 1 ? top : top + i * (bottom - top) / (n - 1);
    const double dy = y - circle.y_px;
    const double half = std::sqrt(std::max(0.0, reach * reach - dy * dy));
    // Clamped as doubles: a huge radius or a centre far off the image must not overflow int.
    const int x0 = static_cast<int>(
        std::clamp(std::ceil(circle.x_px - half), 0.0, static_cast<double>(size.width)));
    const int x1 = static_cast<int>(
        std::clamp(std::floor(circle.x_px + half) + 1.0, 0.0, static_cast<double>(size.width)));
    if (x1 - x0 >= kMinWidthPx) spans.push_back({y, x0, x1 - x0});
  }
  return spans;
}

}  // namespace

namespace {

// A template's per-channel means and its sum of squared deviations (over all channels).
struct TemplateStats {
  std::vector<double> mean;
  double norm2 = 0.0;
};

TemplateStats template_stats(const cv::Mat& templ) {
  const int channels = templ.channels();
  const int w = templ.cols, n = w * channels;
  const std::uint8_t* tp = templ.ptr<std::uint8_t>(0);
  TemplateStats t;
  t.mean.assign(static_cast<std::size_t>(channels), 0.0);
  double t_sum2 = 0.0;
  for (int i = 0; i < n; ++i) {
    t.mean[static_cast<std::size_t>(i % channels)] += tp[i];
    t_sum2 += static_cast<double>(tp[i]) * tp[i];
  }
  t.norm2 = t_sum2;
  for (double& m : t.mean) {
    t.norm2 -= m * m / w;
    m /= w;
  }
  return t;
}

// Running sums of each channel of one row and of its squares, per channel (stride values
// each: 0, then the sums up to every column).
void running_sums(const std::uint8_t* row, int cols, int channels, std::size_t stride,
                  std::vector<double>& run, std::vector<double>& run2) {
  for (int c = 0; c < channels; ++c) {
    double* s1 = &run[static_cast<std::size_t>(c) * stride];
    double* s2 = &run2[static_cast<std::size_t>(c) * stride];
    s1[0] = s2[0] = 0.0;
    for (int x = 0; x < cols; ++x) {
      const double v = row[x * channels + c];
      s1[x + 1] = s1[x] + v;
      s2[x + 1] = s2[x] + v * v;
    }
  }
}

// One row's normalised correlation with templ at every position, into out.
void correlate_row(const std::uint8_t* row, const cv::Mat& templ, const TemplateStats& t,
                   std::size_t stride, const std::vector<double>& run,
                   const std::vector<double>& run2, int positions, float* out) {
  const int channels = templ.channels();
  const int w = templ.cols, n = w * channels;
  const std::uint8_t* tp = templ.ptr<std::uint8_t>(0);
  for (int j = 0; j < positions; ++j) {
    const std::uint8_t* win = row + static_cast<std::ptrdiff_t>(j) * channels;
    std::int32_t products = 0;
    for (int i = 0; i < n; ++i) products += static_cast<std::int32_t>(tp[i]) * win[i];
    double dot = products, var = 0.0;
    for (int c = 0; c < channels; ++c) {
      const double* s1 = &run[static_cast<std::size_t>(c) * stride];
      const double* s2 = &run2[static_cast<std::size_t>(c) * stride];
      const double sum = s1[j + w] - s1[j];
      dot -= t.mean[static_cast<std::size_t>(c)] * sum;
      var += (s2[j + w] - s2[j]) - sum * sum / w;
    }
    const double denom = std::sqrt(std::max(var, 0.0) * std::max(t.norm2, 0.0));
    // A flat window (or template) correlates with nothing, as in OpenCV.
    out[j] = denom > 1e-6 ? static_cast<float>(std::clamp(dot / denom, -1.0, 1.0)) : 0.0f;
  }
}

}  // namespace

void row_template_correlation(const cv::Mat& image, const cv::Mat& templ, cv::Mat& result) {
  const int channels = templ.channels();
  const int w = templ.cols, positions = image.cols - w + 1;
  const std::int64_t products = std::int64_t{image.rows} * positions * w * channels;
  // matchTemplate goes through the DFT with a set-up of tens of microseconds per call: for the
  // small rows of a ball followed at a distance a direct sum is several times cheaper.
  if (products > kDirectCorrelationMaxProducts || positions < 1) {
    cv::matchTemplate(image, templ, result, cv::TM_CCOEFF_NORMED);
    return;
  }
  // sum (T - mean T)(I - mean I) = sum T I - sum_c mean(T_c) sum(I_c): the products in
  // integers (vectorised), the means from running sums.
  const TemplateStats t = template_stats(templ);
  result.create(image.rows, positions, CV_32F);
  const std::size_t stride = static_cast<std::size_t>(image.cols) + 1;
  std::vector<double> run(static_cast<std::size_t>(channels) * stride),
      run2(static_cast<std::size_t>(channels) * stride);
  for (int r = 0; r < image.rows; ++r) {
    const std::uint8_t* row = image.ptr<std::uint8_t>(r);
    running_sums(row, image.cols, channels, stride, run, run2);
    correlate_row(row, templ, t, stride, run, run2, positions, result.ptr<float>(r));
  }
}

cv::Rect interior_rows_region(const Circle& circle, cv::Size size) {
  cv::Rect box;
  for (const RowSpan& s : interior_spans(circle, size))
    box |= cv::Rect(s.x, s.y - kRowSlackPx, s.width, 1 + 2 * kRowSlackPx);
  return box & cv::Rect(cv::Point(0, 0), size);
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
  bool ball_in_view = false;
  double best_shift_px = 0.0, best_match = -1.0, ball_match = -1.0;
};

// One row of the inside against the same row of the right eye (+-kRowSlackPx) at every shift
// in [s_lo, s_hi]: each row on its own, because a floor seen by a level rig has one disparity
// per row and a different one on the next (a joint template over a slanted floor matches
// nowhere).
// The part of span matched: near the left border a close ball's inside is partly left of
// anything the right eye sees at its disparity (its partner cut off), and nothing there can be
// matched at any shift larger than its column. The row is cut where the ball's own shifts stay
// in view, or as far as keeps kMinCutWidthPx pixels (shifts up to the cut can be tested).
RowSpan cut_to_right_view(const RowSpan& span, const ShiftWindow& window) {
  const int end = span.x + span.width;
  const int first =
      std::min(static_cast<int>(std::ceil(window.ball_hi_px + kBallSlackPx)), end - kMinCutWidthPx);
  if (span.x >= first) return span;
  return {span.y, first, end - first};
}

RowMatch match_row(const cv::Mat& left, const cv::Mat& right, const RowSpan& whole,
                   const ShiftWindow& window, const InteriorDepthParams& p,
                   std::vector<float>& match) {
  RowMatch out;
  const RowSpan span = cut_to_right_view(whole, window);
  // Whole shifts s keep the row's columns [x - s, x + width - s) inside the right image.
  const int s_lo =
      std::max(static_cast<int>(std::ceil(window.search_lo_px)), span.x + span.width - right.cols);
  const int s_hi = std::min(static_cast<int>(std::floor(window.search_hi_px)), span.x);
  if (s_hi < s_lo) return out;
  // The ball's own shifts may put this row outside the right image (a close ball at the left
  // border, its partner mostly cut off): then only a strong match elsewhere counts.
  out.ball_in_view =
      s_hi >= window.ball_lo_px - kBallSlackPx && s_lo <= window.ball_hi_px + kBallSlackPx;
  const cv::Mat templ = left(cv::Rect(span.x, span.y, span.width, 1));
  if (mean_std(templ) < p.min_texture) return out;
  out.textured = true;
  match.assign(static_cast<std::size_t>(s_hi - s_lo + 1), -1.0f);
  cv::Mat result;
  const int strip_x = span.x - s_hi, strip_width = span.width + (s_hi - s_lo);
  // The rows y-1..y+1 at once (spans keep a row of slack from the image borders).
  const int y0 = std::max(span.y - kRowSlackPx, 0);
  const int y1 = std::min(span.y + kRowSlackPx, right.rows - 1);
  row_template_correlation(right(cv::Rect(strip_x, y0, strip_width, y1 - y0 + 1)), templ, result);
  // result column j: the row at strip_x + j in the right eye, i.e. shift s_hi - j.
  for (int i = 0; i < result.rows; ++i) {
    const float* row = result.ptr<float>(i);
    for (int j = 0; j < result.cols; ++j) {
      float& m = match[static_cast<std::size_t>(s_hi - j - s_lo)];
      m = std::max(m, row[j]);
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
  if (!r.ball_in_view) return outside && r.best_match >= std::min(0.95, p.min_match + p.min_margin);
  return outside && r.best_match >= p.min_match && r.best_match - r.ball_match >= p.min_margin;
}

}  // namespace

InteriorDepth interior_depth(const cv::Mat& left, const cv::Mat& right, const Circle& circle,
                             const ShiftWindow& window, const InteriorDepthParams& params) {
  InteriorDepth out;
  if (left.empty() || left.type() != right.type() || left.size() != right.size() ||
      left.depth() != CV_8U)
    return out;
  std::vector<float> match;
  std::vector<RowMatch> elsewhere;
  for (const RowSpan& span : interior_spans(circle, left.size())) {
    const RowMatch r = match_row(left, right, span, window, params, match);
    if (!r.textured) continue;
    ++out.rows_textured;
    if (row_elsewhere(r, window, params)) elsewhere.push_back(r);
  }
  out.textured = out.rows_textured >= kMinRowsTextured;
  out.rows_elsewhere = static_cast<int>(elsewhere.size());
  if (elsewhere.empty()) return out;
  // The reason quotes the median row that lies elsewhere.
  std::nth_element(
      elsewhere.begin(), elsewhere.begin() + elsewhere.size() / 2, elsewhere.end(),
      [](const RowMatch& a, const RowMatch& b) { return a.best_shift_px < b.best_shift_px; });
  const RowMatch& median = elsewhere[elsewhere.size() / 2];
  out.best_shift_px = median.best_shift_px;
  out.best_match = median.best_match;
  out.ball_match = median.ball_match;
  // Most textured rows must agree: one row may match a repeated pattern by chance.
  out.contradicts = out.textured && 2 * out.rows_elsewhere > out.rows_textured;
  return out;
}

}  // namespace stereoball::ball_detector
