#include "stereo/core/eye_order.hpp"

#include <algorithm>
#include <cmath>

namespace stereoball::stereo {
namespace {

std::size_t matches_on_row(const cv::Mat& left_rect, const cv::Mat& right_rect,
                           const EyeOrderParams& params) {
  std::size_t n = 0;
  for (const RowMatch& m : match_rows(left_rect, right_rect, params.rows))
    if (std::abs(m.row_residual_px()) <= params.max_row_diff_px) ++n;
  return n;
}

}  // namespace

EyeOrderEvidence check_eye_order(const Rectifier& rectifier, const cv::Mat& left,
                                 const cv::Mat& right, bool rectified,
                                 const EyeOrderParams& params) {
  EyeOrderEvidence out;
  cv::Mat l, r, l_swapped, r_swapped;
  if (rectified) {
    out.matches_as_given = matches_on_row(left, right, params);
    out.matches_swapped = matches_on_row(right, left, params);
  } else {
    // Exchanged: the image given as right goes through the left camera's model and back.
    if (!rectifier.rectify(left, right, l, r).ok() ||
        !rectifier.rectify(right, left, l_swapped, r_swapped).ok())
      return out;
    out.matches_as_given = matches_on_row(l, r, params);
    out.matches_swapped = matches_on_row(l_swapped, r_swapped, params);
  }
  out.swapped =
      out.matches_swapped >= params.min_matches &&
      static_cast<double>(out.matches_swapped) >=
          params.min_ratio * static_cast<double>(std::max<std::size_t>(out.matches_as_given, 1));
  return out;
}

std::optional<std::string> describe_swapped_eyes(const EyeOrderEvidence& evidence,
                                                 const std::string& how_to_fix) {
  if (!evidence.swapped) return std::nullopt;
  return "left and right images look swapped: " + std::to_string(evidence.matches_swapped) +
         " features match on the same rectified row with the eyes exchanged, " +
         std::to_string(evidence.matches_as_given) +
         " as given (a swapped pair has negative disparities, so no ball is found); " + how_to_fix;
}

EyeOrderWatch::EyeOrderWatch(int max_checks, int frames_between, const EyeOrderParams& params)
    : max_checks_(max_checks), frames_between_(std::max(frames_between, 1)), params_(params) {}

bool EyeOrderWatch::due() const {
  return !decided_ && checks_ < max_checks_ && frames_ % frames_between_ == 0;
}

std::optional<EyeOrderEvidence> EyeOrderWatch::step(const Rectifier& rectifier, const cv::Mat& left,
                                                    const cv::Mat& right, bool rectified) {
  const bool check = due();
  ++frames_;
  if (!check || left.empty() || right.empty()) return std::nullopt;
  ++checks_;
  EyeOrderEvidence e = check_eye_order(rectifier, left, right, rectified, params_);
  decided_ = std::max(e.matches_as_given, e.matches_swapped) >= params_.min_matches;
  return e;
}

void EyeOrderWatch::skip() {
  if (due()) ++checks_;
  ++frames_;
}

bool EyeOrderWatch::given_up() const {
  return !decided_ && checks_ >= max_checks_;
}

void EyeOrderWatch::reset() {
  frames_ = checks_ = 0;
  decided_ = false;
}

}  // namespace stereoball::stereo
