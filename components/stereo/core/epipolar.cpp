#include "stereo/core/epipolar.hpp"

#include <cmath>

namespace stereoball::stereo {

Status EpipolarParams::validate() const {
  if (!std::isfinite(max_row_diff_px) || max_row_diff_px < 0.0 || max_row_diff_px > 100.0) {
    return Error{"max_row_diff_px: must be in [0, 100] pixels, got " +
                 std::to_string(max_row_diff_px)};
  }
  return {};
}

EpipolarCheck::EpipolarCheck(const EpipolarParams& params) : params_(params) {}

EpipolarMatch EpipolarCheck::check(cv::Point2d left_px, cv::Point2d right_px) const {
  EpipolarMatch m;
  m.row_residual_px = std::abs(left_px.y - right_px.y);
  m.accepted = m.row_residual_px <= params_.max_row_diff_px;
  m.row_px = 0.5 * (left_px.y + right_px.y);
  m.x_left_px = left_px.x;
  m.x_right_px = right_px.x;
  return m;
}

std::optional<CandidatePair> EpipolarCheck::best_pair(
    const std::vector<cv::Point2d>& left_px, const std::vector<cv::Point2d>& right_px) const {
  std::optional<CandidatePair> best;
  for (std::size_t i = 0; i < left_px.size(); ++i) {
    for (std::size_t j = 0; j < right_px.size(); ++j) {
      const EpipolarMatch m = check(left_px[i], right_px[j]);
      // A point in front of the rig appears further left in the right eye.
      if (!m.accepted || m.x_left_px < m.x_right_px) continue;
      if (!best || m.row_residual_px < best->match.row_residual_px) best = CandidatePair{i, j, m};
    }
  }
  return best;
}

}  // namespace stereoball::stereo
