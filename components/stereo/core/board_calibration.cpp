#include "stereo/core/board_calibration.hpp"

#include "stereo/core/pair_error.hpp"
#include "stereo/core/rectifier.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace stereoball::stereo {
namespace {

std::vector<cv::Point3f> board_points(const BoardCalibrationParams& p) {
  std::vector<cv::Point3f> pts;
  for (int row = 0; row < p.inner_corners.height; ++row) {
    for (int col = 0; col < p.inner_corners.width; ++col) {
      pts.emplace_back(static_cast<float>(col * p.square_m), static_cast<float>(row * p.square_m),
                       0.0f);
    }
  }
  return pts;
}

std::vector<double> to_vector(const cv::Mat& m) {
  cv::Mat flat = m.reshape(1, 1);
  flat.convertTo(flat, CV_64F);
  return std::vector<double>(flat.begin<double>(), flat.end<double>());
}

std::vector<cv::Point2d> to_double(const std::vector<cv::Point2f>& pts) {
  return std::vector<cv::Point2d>(pts.begin(), pts.end());
}

}  // namespace

Status BoardCalibrationParams::validate() const {
  if (inner_corners.width < 2 || inner_corners.height < 2 || inner_corners.width > 100 ||
      inner_corners.height > 100) {
    return Error{"inner_corners: each dimension must be in [2, 100]"};
  }
  if (!std::isfinite(square_m) || square_m <= 0.0 || square_m > 10.0) {
    return Error{"square_m: must be in (0, 10] metres, got " + std::to_string(square_m)};
  }
  if (min_pairs < 3 || min_pairs > 1000) {
    return Error{"min_pairs: must be in [3, 1000], got " + std::to_string(min_pairs)};
  }
  if (!std::isfinite(outlier_ratio) || outlier_ratio < 0.0 || outlier_ratio > 100.0) {
    return Error{"outlier_ratio: must be 0 (keep every pair) or in (0, 100], got " +
                 std::to_string(outlier_ratio)};
  }
  if (!std::isfinite(outlier_min_px) || outlier_min_px < 0.0 || outlier_min_px > 100.0) {
    return Error{"outlier_min_px: must be in [0, 100] pixels, got " +
                 std::to_string(outlier_min_px)};
  }
  if (subpix_window_px < 3 || subpix_window_px > 51) {
    return Error{"subpix_window_px: must be in [3, 51], got " + std::to_string(subpix_window_px)};
  }
  if (!(rectify.alpha == -1.0 || (rectify.alpha >= 0.0 && rectify.alpha <= 1.0))) {
    return Error{"rectify.alpha: must be -1 or in [0, 1], got " + std::to_string(rectify.alpha)};
  }
  return {};
}

std::optional<cv::Size> parse_board_size(const std::string& text) {
  int cols = 0, rows = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &cols, &x, &rows, &extra) != 3) return std::nullopt;
  if ((x != 'x' && x != 'X') || cols < 2 || rows < 2 || cols > 50 || rows > 50) return std::nullopt;
  return cv::Size(cols, rows);
}

std::optional<std::vector<cv::Point2f>> find_board_corners(const cv::Mat& image,
                                                           const BoardCalibrationParams& params) {
  if (image.empty()) return std::nullopt;
  cv::Mat grey;
  if (image.channels() == 3) {
    cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  } else if (image.channels() == 1) {
    grey = image;
  } else {
    return std::nullopt;
  }
  std::vector<cv::Point2f> corners;
  const int flags = cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE;
  if (!cv::findChessboardCorners(grey, params.inner_corners, corners, flags)) return std::nullopt;
  const int half = params.subpix_window_px / 2;
  cv::cornerSubPix(grey, corners, cv::Size(half, half), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 50, 1e-3));
  return corners;
}

bool align_corner_order(const std::vector<cv::Point2f>& left_px,
                        std::vector<cv::Point2f>& right_px) {
  if (left_px.size() < 2 || left_px.size() != right_px.size()) return false;
  // The board diagonal points the same way in both eyes of a side-by-side rig.
  const cv::Point2f dl = left_px.back() - left_px.front();
  const cv::Point2f dr = right_px.back() - right_px.front();
  if (dl.dot(dr) >= 0.0f) return false;
  std::reverse(right_px.begin(), right_px.end());
  return true;
}

std::pair<double, double> rectified_row_error_px(const StereoCalibration& calib,
                                                 const std::vector<PairCorners>& pairs) {
  auto rectifier = Rectifier::create(calib);
  if (!rectifier) return {0.0, 0.0};
  double sum = 0.0, max = 0.0;
  std::size_t n = 0;
  for (const PairCorners& pair : pairs) {
    const auto l = rectifier->rectify_points(Eye::kLeft, to_double(pair.left_px));
    const auto r = rectifier->rectify_points(Eye::kRight, to_double(pair.right_px));
    for (std::size_t i = 0; i < std::min(l.size(), r.size()); ++i) {
      const double e = std::abs(l[i].y - r[i].y);
      sum += e;
      max = std::max(max, e);
      ++n;
    }
  }
  return {n ? sum / static_cast<double>(n) : 0.0, max};
}

namespace {

// One calibration of exactly these pairs (no dropping); row errors not yet filled in.
BoardCalibrationResult calibrate_pairs(const std::vector<PairCorners>& pairs, cv::Size image_size,
                                       const BoardCalibrationParams& params) {
  const std::vector<std::vector<cv::Point3f>> object(pairs.size(), board_points_m(params));
  std::vector<std::vector<cv::Point2f>> left, right;
  BoardCalibrationResult out;
  for (const PairCorners& p : pairs) {
    left.push_back(p.left_px);
    right.push_back(p.right_px);
    out.pair_names.push_back(p.name);
  }
  // Each camera alone first: a well-conditioned start for the joint refinement.
  cv::Mat k1, d1, k2, d2, rvecs, tvecs;
  out.left_rms_px = cv::calibrateCamera(object, left, image_size, k1, d1, rvecs, tvecs);
  out.right_rms_px = cv::calibrateCamera(object, right, image_size, k2, d2, rvecs, tvecs);
  cv::Mat r, t, e, f, per_view;
  const double rms = cv::stereoCalibrate(
      object, left, right, k1, d1, k2, d2, image_size, r, t, e, f, per_view,
      cv::CALIB_USE_INTRINSIC_GUESS,
      cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-9));
  StereoCalibration& c = out.calibration;
  c.image_size = image_size;
  c.k1 = cv::Matx33d(k1);
  c.d1 = to_vector(d1);
  c.k2 = cv::Matx33d(k2);
  c.d2 = to_vector(d2);
  c.r = cv::Matx33d(r);
  c.t = cv::Vec3d(t.reshape(1, 3));
  rectify_calibration(c, params.rectify);
  c.rms_px = rms;
  for (int i = 0; i < per_view.rows; ++i) {
    const double el = per_view.at<double>(i, 0), er = per_view.at<double>(i, 1);
    c.per_pair_rms_px.push_back(std::sqrt(0.5 * (el * el + er * er)));
  }
  return out;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

std::string fixed2(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", v);
  return buf;
}

// Tries to drop the pair that fits the current calibration worst: it goes when the other
// pairs, calibrated without it, cannot explain it either (error far above their own).
std::optional<DroppedPair> drop_worst_pair(std::vector<PairCorners>& kept,
                                           BoardCalibrationResult& current, cv::Size image_size,
                                           const BoardCalibrationParams& params) {
  const auto& errors = current.calibration.per_pair_rms_px;
  const auto worst =
      static_cast<std::size_t>(std::max_element(errors.begin(), errors.end()) - errors.begin());
  std::vector<PairCorners> rest = kept;
  rest.erase(rest.begin() + static_cast<std::ptrdiff_t>(worst));
  BoardCalibrationResult without = calibrate_pairs(rest, image_size, params);
  const PairError e = stereo_pair_error(without.calibration, board_points_m(params),
                                        kept[worst].left_px, kept[worst].right_px);
  const double rest_median = median(without.calibration.per_pair_rms_px);
  const double limit = std::max(params.outlier_ratio * rest_median, params.outlier_min_px);
  if (!(e.rms_px > limit)) return std::nullopt;
  DroppedPair d{kept[worst].name, e.rms_px, rest_median, e.mean_row_error_px, ""};
  d.reason = "stereo error " + fixed2(e.rms_px) + " px against the other pairs' calibration (" +
             "their median " + fixed2(rest_median) + " px, limit " + fixed2(limit) + " px; left " +
             fixed2(e.left_rms_px) + " px, right " + fixed2(e.right_rms_px) +
             " px, rectified row error " + fixed2(e.mean_row_error_px) +
             " px): the board moved between the two shots or a corner is wrong";
  kept = std::move(rest);
  current = std::move(without);
  return d;
}

}  // namespace

std::optional<std::string> single_camera_fit_problem(const BoardCalibrationResult& result,
                                                     double limit_px) {
  if (!(result.left_rms_px > limit_px) && !(result.right_rms_px > limit_px)) return std::nullopt;
  return "each camera alone fits its board corners only to " + fixed2(result.left_rms_px) +
         " px (left) and " + fixed2(result.right_rms_px) + " px (right), above " +
         fixed2(limit_px) +
         " px: the images, not the pairing, limit this calibration. Lock the focus (an "
         "autofocus camera changes its focal length between shots), keep the board flat on a "
         "rigid backing and still while both cameras expose (rolling shutter), and check that "
         "--board names the inner corners of this board";
}

std::vector<cv::Point3f> board_points_m(const BoardCalibrationParams& params) {
  return board_points(params);
}

Result<BoardCalibrationResult> calibrate_stereo(const std::vector<PairCorners>& pairs,
                                                cv::Size image_size,
                                                const BoardCalibrationParams& params) {
  if (auto error = params.validate(); !error) return Error{error.error()};
  if (image_size.width <= 0 || image_size.height <= 0) return Error{"image_size: must be > 0"};
  const std::size_t expected = static_cast<std::size_t>(params.inner_corners.area());
  for (const PairCorners& p : pairs) {
    if (p.left_px.size() != expected || p.right_px.size() != expected) {
      return Error{"pair " + p.name + ": expected " + std::to_string(expected) +
                   " corners per eye"};
    }
  }
  if (static_cast<int>(pairs.size()) < params.min_pairs) {
    return Error{"only " + std::to_string(pairs.size()) + " usable pairs, need at least " +
                 std::to_string(params.min_pairs) + " (min_pairs)"};
  }
  BoardCalibrationResult out = calibrate_pairs(pairs, image_size, params);
  if (auto error = validate_calibration(out.calibration); !error)
    return Error{"calibration result invalid: " + error.error()};
  const double all_rms = out.calibration.rms_px;
  const auto [all_mean_row, all_max_row] = rectified_row_error_px(out.calibration, pairs);
  std::vector<PairCorners> kept = pairs;
  std::vector<DroppedPair> dropped;
  while (params.outlier_ratio > 0.0 && static_cast<int>(kept.size()) > params.min_pairs) {
    auto d = drop_worst_pair(kept, out, image_size, params);
    if (!d) break;
    dropped.push_back(std::move(*d));
  }
  out.dropped = std::move(dropped);
  out.all_pairs_rms_px = all_rms;
  out.all_pairs_mean_row_error_px = all_mean_row;
  out.all_pairs_max_row_error_px = all_max_row;
  if (auto error = validate_calibration(out.calibration); !error)
    return Error{"calibration result invalid: " + error.error()};
  std::tie(out.mean_rectified_row_error_px, out.max_rectified_row_error_px) =
      rectified_row_error_px(out.calibration, kept);
  return out;
}

}  // namespace stereoball::stereo
