#include "stereo/core/row_check.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

namespace stereoball::stereo {
namespace {

cv::Mat to_grey(const cv::Mat& image) {
  if (image.channels() == 1) return image;
  cv::Mat grey;
  cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  return grey;
}

// Offset of the parabola vertex through (-1, a), (0, b), (1, c), in [-0.5, 0.5].
double parabola_peak(float a, float b, float c) {
  const double denom = a - 2.0 * b + c;
  if (std::abs(denom) < 1e-12) return 0.0;
  return std::clamp(0.5 * (a - c) / denom, -0.5, 0.5);
}

// Best match of the block around `at` in `src` inside `search` of `dst`; sub-pixel.
std::optional<cv::Point2d> match_block(const cv::Mat& src, const cv::Mat& dst, cv::Point at,
                                       cv::Rect search, const RowCheckParams& p) {
  const int h = p.half_block_px;
  const cv::Rect block(at.x - h, at.y - h, 2 * h + 1, 2 * h + 1);
  search &= cv::Rect(0, 0, dst.cols, dst.rows);
  if ((block & cv::Rect(0, 0, src.cols, src.rows)) != block) return std::nullopt;
  if (search.width < block.width + 2 || search.height < block.height + 2) return std::nullopt;
  cv::Mat score;
  cv::matchTemplate(dst(search), src(block), score, cv::TM_CCOEFF_NORMED);
  double best = 0.0;
  cv::Point loc;
  cv::minMaxLoc(score, nullptr, &best, nullptr, &loc);
  if (best < p.min_score) return std::nullopt;
  double dx = 0.0, dy = 0.0;
  if (loc.x > 0 && loc.x < score.cols - 1) {
    dx = parabola_peak(score.at<float>(loc.y, loc.x - 1), score.at<float>(loc.y, loc.x),
                       score.at<float>(loc.y, loc.x + 1));
  }
  if (loc.y > 0 && loc.y < score.rows - 1) {
    dy = parabola_peak(score.at<float>(loc.y - 1, loc.x), score.at<float>(loc.y, loc.x),
                       score.at<float>(loc.y + 1, loc.x));
  }
  return cv::Point2d(search.x + loc.x + h + dx, search.y + loc.y + h + dy);
}

}  // namespace

Status RowCheckParams::validate() const {
  if (max_features < 1 || max_features > 100000)
    return Error{"max_features: must be in [1, 100000]"};
  if (half_block_px < 2 || half_block_px > 50) return Error{"half_block_px: must be in [2, 50]"};
  if (max_row_search_px < 1 || max_row_search_px > 200) {
    return Error{"max_row_search_px: must be in [1, 200]"};
  }
  if (max_disparity_px < 0 || max_disparity_px > 5000) {
    return Error{"max_disparity_px: must be in [0, 5000]"};
  }
  if (!(min_score > 0.0 && min_score <= 1.0)) return Error{"min_score: must be in (0, 1]"};
  if (!(max_backmatch_px > 0.0)) return Error{"max_backmatch_px: must be > 0"};
  return {};
}

std::vector<RowMatch> match_rows(const cv::Mat& left, const cv::Mat& right,
                                 const RowCheckParams& p) {
  if (left.empty() || right.empty() || left.size() != right.size()) return {};
  const cv::Mat l = to_grey(left), r = to_grey(right);
  std::vector<cv::Point2f> corners;
  cv::goodFeaturesToTrack(l, corners, p.max_features, 0.01, 2.0 * p.half_block_px);
  const int h = p.half_block_px, rows = p.max_row_search_px, margin = h + 2;
  std::vector<RowMatch> out;
  for (const cv::Point2f& c : corners) {
    const cv::Point at(cvRound(c.x), cvRound(c.y));
    const cv::Rect fwd(at.x - p.max_disparity_px - h - 1, at.y - rows - h - 1,
                       p.max_disparity_px + 2 * margin, 2 * (rows + h + 1) + 1);
    const auto m = match_block(l, r, at, fwd, p);
    if (!m) continue;
    // Match back into the left image: a wrong (repeated-texture) match rarely returns home.
    const cv::Point back_at(cvRound(m->x), cvRound(m->y));
    const cv::Rect bwd(back_at.x - margin, back_at.y - rows - h - 1,
                       p.max_disparity_px + 2 * margin, 2 * (rows + h + 1) + 1);
    const auto b = match_block(r, l, back_at, bwd, p);
    if (!b || std::hypot(b->x - at.x, b->y - at.y) > p.max_backmatch_px) continue;
    out.push_back({cv::Point2d(at), *m});
  }
  return out;
}

RowResidualStats summarize_rows(const std::vector<RowMatch>& matches) {
  RowResidualStats s;
  s.count = matches.size();
  if (matches.empty()) return s;
  std::vector<double> abs_dy;
  double sum_signed = 0.0;
  for (const RowMatch& m : matches) {
    abs_dy.push_back(std::abs(m.row_residual_px()));
    sum_signed += m.row_residual_px();
  }
  std::sort(abs_dy.begin(), abs_dy.end());
  const double n = static_cast<double>(abs_dy.size());
  for (double v : abs_dy) s.mean_abs_px += v / n;
  s.median_abs_px = abs_dy[abs_dy.size() / 2];
  s.p90_abs_px = abs_dy[std::min(abs_dy.size() - 1, static_cast<std::size_t>(0.9 * n))];
  s.max_abs_px = abs_dy.back();
  s.mean_signed_px = sum_signed / n;
  return s;
}

}  // namespace stereoball::stereo
