#include "image_measures.hpp"

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>

#include "stereo/core/row_check.hpp"

namespace stereoball::doctor {
namespace {

cv::Mat grey(const cv::Mat& image) {
  if (image.channels() == 1) return image;
  cv::Mat out;
  cv::cvtColor(image, out, cv::COLOR_BGR2GRAY);
  return out;
}

}  // namespace

EyeImageStats measure_eye(const cv::Mat& image) {
  EyeImageStats s;
  if (image.empty()) return s;
  const cv::Mat g = grey(image);
  s.mean = cv::mean(g)[0];
  const double n = static_cast<double>(g.total());
  s.dark_fraction = cv::countNonZero(g <= 2) / n;
  s.bright_fraction = cv::countNonZero(g >= 253) / n;
  cv::Mat lap;
  cv::Laplacian(g, lap, CV_64F);
  cv::Scalar mean, stddev;
  cv::meanStdDev(lap, mean, stddev);
  s.laplacian_var = stddev[0] * stddev[0];
  return s;
}

std::pair<std::size_t, std::size_t> disparity_signs(const cv::Mat& left_rect,
                                                    const cv::Mat& right_rect,
                                                    const SignParams& params) {
  auto orb = cv::ORB::create(params.max_features);
  std::vector<cv::KeyPoint> kl, kr;
  cv::Mat dl, dr;
  orb->detectAndCompute(grey(left_rect), cv::noArray(), kl, dl);
  orb->detectAndCompute(grey(right_rect), cv::noArray(), kr, dr);
  if (dl.empty() || dr.empty()) return {0, 0};
  cv::BFMatcher matcher(cv::NORM_HAMMING, /*crossCheck=*/true);
  std::vector<cv::DMatch> matches;
  matcher.match(dl, dr, matches);
  std::size_t positive = 0, negative = 0;
  for (const auto& m : matches) {
    const cv::Point2f l = kl[m.queryIdx].pt, r = kr[m.trainIdx].pt;
    if (std::abs(l.y - r.y) > params.max_row_diff_px) continue;
    const double dx = l.x - r.x;
    if (std::abs(dx) < params.min_abs_disparity_px) continue;
    (dx > 0 ? positive : negative)++;
  }
  return {positive, negative};
}

void add_pair(StereoMeasures& m, const stereo::Rectifier* rectifier, const cv::Mat& left,
              const cv::Mat& right, bool rectified, const SignParams& params) {
  if (left.empty() || right.empty()) return;
  ++m.pairs;
  m.left = measure_eye(left);
  m.right = measure_eye(right);
  if (!rectifier) return;
  cv::Mat l = left, r = right;
  if (!rectified) {
    if (auto st = rectifier->rectify(left, right, l, r); !st) {
      m.stereo_error = "cannot rectify: " + st.error();
      return;
    }
  }
  const auto [positive, negative] = disparity_signs(l, r, params);
  m.positive += positive;
  m.negative += negative;
  for (const auto& match : stereo::match_rows(l, r, stereo::RowCheckParams{}))
    m.abs_row_px.push_back(std::abs(match.row_residual_px()));
  ++m.stereo_pairs;
}

}  // namespace stereoball::doctor
