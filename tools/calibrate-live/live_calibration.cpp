#include "live_calibration.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "stereo/core/calibration.hpp"

namespace stereoball::calibrate_live {
namespace {

std::string format(const char* fmt, double a, double b = 0) {
  char text[160];
  std::snprintf(text, sizeof text, fmt, a, b);
  return text;
}

double view_distance(const stereo::BoardViewParams& a, const stereo::BoardViewParams& b) {
  return std::abs(a.x - b.x) + std::abs(a.y - b.y) + std::abs(a.size - b.size) +
         std::abs(a.skew - b.skew);
}

double mean_disparity_px(const std::vector<cv::Point2f>& left,
                         const std::vector<cv::Point2f>& right) {
  double sum = 0;
  for (size_t i = 0; i < left.size(); ++i) sum += left[i].x - right[i].x;
  return left.empty() ? 0 : sum / static_cast<double>(left.size());
}

// The axis of the image coverage that lags most, as advice for the person with the board.
std::string coverage_advice(const std::array<double, 4>& progress, double depth) {
  static const char* const kAdvice[] = {
      "move the board toward the left and right edges of the view",
      "move the board toward the top and bottom of the view",
      "bring the board nearer so it fills more of the view, and farther",
      "tilt the board (turn it about its vertical and horizontal axes)",
  };
  size_t worst = 0;
  for (size_t i = 1; i < progress.size(); ++i)
    if (progress[i] < progress[worst]) worst = i;
  if (depth < progress[worst]) return "show the board at two distances, one twice the other";
  return kAdvice[worst];
}

}  // namespace

Status LiveParams::validate() const {
  if (auto st = board.validate(); !st) return st;
  if (auto st = still.validate(); !st) return st;
  if (target_poses < board.min_pairs || target_poses > 200)
    return Error{"target_poses: must be in [min_pairs = " + std::to_string(board.min_pairs) +
                 ", 200], got " + std::to_string(target_poses)};
  if (!(min_pose_distance >= 0 && min_pose_distance <= 2))
    return Error{format("min_pose_distance: must be in [0, 2], got %g", min_pose_distance)};
  if (!(max_rms_px > 0 && max_rms_px <= 10))
    return Error{format("max_rms_px: must be in (0, 10] px, got %g", max_rms_px)};
  if (!(max_row_error_px > 0 && max_row_error_px <= 10))
    return Error{format("max_row_error_px: must be in (0, 10] px, got %g", max_row_error_px)};
  if (!(min_baseline_m >= 0) || !(max_baseline_m >= 0) ||
      (max_baseline_m > 0 && max_baseline_m < min_baseline_m))
    return Error{format("baseline range: need 0 <= min <= max (0 = unchecked), got [%g, %g] m",
                        min_baseline_m, max_baseline_m)};
  if (one_eye_hint_ns < 0) return Error{"one_eye_hint_ns: must be >= 0"};
  return {};
}

double depth_progress(const std::vector<double>& disparities_px) {
  double lo = 0, hi = 0;
  bool any = false;
  for (double d : disparities_px) {
    if (!(d > 0)) continue;
    lo = any ? std::min(lo, d) : d;
    hi = any ? std::max(hi, d) : d;
    any = true;
  }
  if (!any) return 0;
  return std::min(1.0, (1.0 - lo / hi) / 0.5);
}

LiveCalibration::LiveCalibration(const LiveParams& params, cv::Size image_size)
    : params_(params), image_size_(image_size), selector_(params.still) {}

std::optional<PoseRecord> LiveCalibration::add_frame(int64_t left_stamp_ns,
                                                     const std::vector<cv::Point2f>& left_px,
                                                     int64_t right_stamp_ns,
                                                     const std::vector<cv::Point2f>& right_px) {
  if (frames_++ == 0) first_stamp_ns_ = std::min(left_stamp_ns, right_stamp_ns);
  frames_left_ += !left_px.empty();
  frames_right_ += !right_px.empty();
  last_stamp_ns_ = std::max(left_stamp_ns, right_stamp_ns);
  const bool one_eye = left_px.empty() != right_px.empty();
  if (!one_eye)
    one_eye_since_ns_ = -1;
  else if (one_eye_since_ns_ < 0)
    one_eye_since_ns_ = last_stamp_ns_;

  auto still = selector_.add(stereo::Eye::kLeft, left_stamp_ns, left_px);
  if (!still)
    still = selector_.add(stereo::Eye::kRight, right_stamp_ns, right_px);
  else
    selector_.add(stereo::Eye::kRight, right_stamp_ns, right_px);
  if (!still) return std::nullopt;

  std::vector<cv::Point2f> right = still->right_px;
  stereo::align_corner_order(still->left_px, right);
  const auto view =
      stereo::board_view_params(still->left_px, params_.board.inner_corners, image_size_);
  if (!view) return std::nullopt;
  if (too_close_to_taken(*view)) {
    ++duplicates_;
    return std::nullopt;
  }
  PoseRecord record;
  record.index = static_cast<int>(records_.size()) + 1;
  record.view = *view;
  record.disparity_px = mean_disparity_px(still->left_px, right);
  record.left_stamp_ns = still->left_stamp_ns;
  record.right_stamp_ns = still->right_stamp_ns;
  poses_.push_back({"pose " + std::to_string(record.index), still->left_px, right});
  records_.push_back(record);
  coverage_.add(*view);
  disparities_px_.push_back(record.disparity_px);
  return record;
}

bool LiveCalibration::too_close_to_taken(const stereo::BoardViewParams& view) const {
  return std::any_of(records_.begin(), records_.end(), [&](const PoseRecord& r) {
    return view_distance(r.view, view) < params_.min_pose_distance;
  });
}

std::string LiveCalibration::hint(const stereo::EyeStillness& left,
                                  const stereo::EyeStillness& right) const {
  if (one_eye_since_ns_ >= 0 && last_stamp_ns_ - one_eye_since_ns_ >= params_.one_eye_hint_ns)
    return std::string("the board is seen by the ") + (left.board_seen ? "left" : "right") +
           " eye only: move it into both views";
  if (!left.board_seen && !right.board_seen)
    return frames_left_ + frames_right_ == 0 && last_stamp_ns_ - first_stamp_ns_ >= 1'000'000'000
               ? no_board_text() + " yet: show the whole board, and check --board"
               : "show the whole board to both cameras";
  if (left.board_seen && right.board_seen &&
      std::min(left.still_ns, right.still_ns) < params_.still.still_ns)
    return "hold the board still";
  if (enough_poses()) return "enough poses: the verdict follows";
  return coverage_advice(coverage_.progress(), depth_progress(disparities_px_));
}

Progress LiveCalibration::progress() const {
  Progress p;
  p.poses = static_cast<int>(records_.size());
  p.target_poses = params_.target_poses;
  p.coverage = coverage_.progress();
  p.depth_coverage = depth_progress(disparities_px_);
  p.left = selector_.stillness(stereo::Eye::kLeft);
  p.right = selector_.stillness(stereo::Eye::kRight);
  p.frames = frames_;
  p.frames_board_left = frames_left_;
  p.frames_board_right = frames_right_;
  p.skipped_duplicates = duplicates_;
  p.hint = hint(p.left, p.right);
  return p;
}

bool LiveCalibration::enough_poses() const {
  return static_cast<int>(records_.size()) >= params_.target_poses;
}

std::string LiveCalibration::no_board_text() const {
  return "no " + std::to_string(params_.board.inner_corners.width) + "x" +
         std::to_string(params_.board.inner_corners.height) + " board found";
}

Result<Verdict> LiveCalibration::finish() const {
  if (frames_ > 0 && frames_left_ + frames_right_ == 0)
    return Error{no_board_text() + " in any of " + std::to_string(frames_) +
                 " frames: show the whole board, and check --board (inner corners: a board of "
                 "10x7 squares has 9x6)"};
  if (static_cast<int>(poses_.size()) < params_.board.min_pairs)
    return Error{"only " + std::to_string(poses_.size()) + " still poses taken, need at least " +
                 std::to_string(params_.board.min_pairs) +
                 ": hold the board still in both views at more places"};
  auto calibrated = stereo::calibrate_stereo(poses_, image_size_, params_.board);
  if (!calibrated) return Error{calibrated.error()};
  Verdict v;
  v.result = std::move(calibrated.value());
  const auto& c = v.result.calibration;
  for (size_t i = 0; i < v.result.pair_names.size() && i < c.per_pair_rms_px.size(); ++i)
    v.per_pose.push_back({v.result.pair_names[i], c.per_pair_rms_px[i]});
  if (auto order = stereo::check_camera_order(c); !order)
    v.failures.push_back(order.error() +
                         ": swap left_device and right_device in the camera_server config");
  if (c.rms_px > params_.max_rms_px)
    v.failures.push_back(
        format("stereo RMS %.3f px above %.3f px: poses with motion blur or a "
               "bent board; hold it flat and still",
               c.rms_px, params_.max_rms_px));
  if (v.result.mean_rectified_row_error_px > params_.max_row_error_px)
    v.failures.push_back(
        format("mean rectified row error %.3f px above %.3f px: take more poses "
               "over the whole view, board flat and still",
               v.result.mean_rectified_row_error_px, params_.max_row_error_px));
  const double baseline_m = std::abs(c.t[0]);
  if (params_.min_baseline_m > 0 && baseline_m < params_.min_baseline_m)
    v.failures.push_back(
        format("baseline %.4f m below the rig's %.4f m: check the board's "
               "square size (--square-mm)",
               baseline_m, params_.min_baseline_m));
  if (params_.max_baseline_m > 0 && baseline_m > params_.max_baseline_m)
    v.failures.push_back(
        format("baseline %.4f m above the rig's %.4f m: check the board's "
               "square size (--square-mm)",
               baseline_m, params_.max_baseline_m));
  const auto cov = coverage_.progress();
  if (!coverage_.complete())
    v.warnings.push_back(
        format("image coverage short (x %.0f %%, y %.0f %%, ...): the "
               "calibration may be poor near the edges",
               100 * cov[0], 100 * cov[1]));
  if (const auto problem = stereo::single_camera_fit_problem(v.result))
    v.warnings.push_back(*problem);
  if (depth_progress(disparities_px_) < 1)
    v.warnings.push_back("depth coverage short: show the board near and twice as far");
  v.pass = v.failures.empty();
  return v;
}

}  // namespace stereoball::calibrate_live
