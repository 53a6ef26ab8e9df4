#include "stereo/core/rectifier.hpp"

#include "stereo/core/bilinear_remap.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>

namespace stereoball::stereo {
namespace {

cv::Mat distortion_mat(const std::vector<double>& d) {
  if (d.empty()) return cv::Mat();
  return cv::Mat(d, true).reshape(1, 1);
}

std::string size_text(cv::Size s) {
  return std::to_string(s.width) + "x" + std::to_string(s.height);
}

const char* eye_name(Eye eye) {
  return eye == Eye::kLeft ? "left" : "right";
}

}  // namespace

Result<Rectifier> Rectifier::create(const StereoCalibration& calib) {
  if (auto error = validate_calibration(calib); !error) return Error{error.error()};
  return Rectifier(calib);
}

Rectifier::Rectifier(const StereoCalibration& calib) : calib_(calib) {
  cv::initUndistortRectifyMap(cv::Mat(calib.k1), distortion_mat(calib.d1), cv::Mat(calib.r1),
                              cv::Mat(calib.p1), calib.image_size, CV_16SC2, left_.xy, left_.frac);
  cv::initUndistortRectifyMap(cv::Mat(calib.k2), distortion_mat(calib.d2), cv::Mat(calib.r2),
                              cv::Mat(calib.p2), calib.image_size, CV_16SC2, right_.xy,
                              right_.frac);
  left_.row_blocks = make_row_blocks(left_.xy, calib.image_size.height);
  right_.row_blocks = make_row_blocks(right_.xy, calib.image_size.height);
}

cv::Mat Rectifier::make_row_blocks(const cv::Mat& xy, int raw_rows) {
  const int blocks = (xy.cols + kRowBlockCols - 1) / kRowBlockCols;
  cv::Mat out(xy.rows, blocks, CV_32SC2);
  for (int r = 0; r < xy.rows; ++r) {
    const short* map = xy.ptr<short>(r);
    cv::Vec2i* block = out.ptr<cv::Vec2i>(r);
    for (int b = 0; b < blocks; ++b) {
      int lo = raw_rows, hi = 0;
      for (int c = b * kRowBlockCols; c < std::min(xy.cols, (b + 1) * kRowBlockCols); ++c) {
        // The look-up reads source rows y and y + 1; those outside the image count as zero.
        const int y = map[2 * c + 1];
        const int from = std::clamp(y, 0, raw_rows), to = std::clamp(y + 2, 0, raw_rows);
        if (to <= from) continue;
        lo = std::min(lo, from);
        hi = std::max(hi, to);
      }
      block[b] = hi > lo ? cv::Vec2i(lo, hi) : cv::Vec2i(0, 0);
    }
  }
  return out;
}

cv::Range Rectifier::raw_rows(Eye eye, cv::Rect roi) const {
  roi &= cv::Rect(cv::Point(0, 0), calib_.image_size);
  if (roi.empty()) return cv::Range(0, 0);
  const cv::Mat& blocks = maps(eye).row_blocks;
  const int first = roi.x / kRowBlockCols, last = (roi.x + roi.width - 1) / kRowBlockCols;
  int lo = calib_.image_size.height, hi = 0;
  for (int r = roi.y; r < roi.y + roi.height; ++r) {
    const cv::Vec2i* block = blocks.ptr<cv::Vec2i>(r);
    for (int b = first; b <= last; ++b) {
      if (block[b][0] >= block[b][1]) continue;  // reads only pixels outside the image
      lo = std::min(lo, block[b][0]);
      hi = std::max(hi, block[b][1]);
    }
  }
  return hi > lo ? cv::Range(lo, hi) : cv::Range(0, 0);
}

Status Rectifier::check_size(Eye eye, const cv::Mat& raw) const {
  if (raw.empty()) return Error{std::string(eye_name(eye)) + " image is empty"};
  if (raw.size() != calib_.image_size) {
    return Error{std::string(eye_name(eye)) + " image is " + size_text(raw.size()) +
                 " but the calibration is for " + size_text(calib_.image_size)};
  }
  return {};
}

Status Rectifier::rectify_eye(Eye eye, const cv::Mat& raw, cv::Mat& out) const {
  if (auto error = check_size(eye, raw); !error) return error;
  const EyeMaps& m = maps(eye);
  remap_bilinear(raw, out, m.xy, m.frac);
  return {};
}

Status Rectifier::rectify_eye_region(Eye eye, const cv::Mat& raw, cv::Rect roi,
                                     cv::Mat& out) const {
  if (auto error = check_size(eye, raw); !error) return error;
  if (out.size() != calib_.image_size || out.type() != raw.type())
    return Error{std::string("rectify_eye_region: output must be ") + size_text(calib_.image_size) +
                 " of the raw frame's type"};
  roi &= cv::Rect(cv::Point(0, 0), calib_.image_size);
  if (roi.empty()) return {};
  const EyeMaps& m = maps(eye);
  cv::Mat target = out(roi);
  // The LUT rows/columns of the region map it from anywhere in the raw frame.
  remap_bilinear(raw, target, m.xy(roi), m.frac(roi));
  return {};
}

Status Rectifier::rectify(const cv::Mat& left, const cv::Mat& right, cv::Mat& left_out,
                          cv::Mat& right_out) const {
  // Check both before writing either, so a bad pair leaves the outputs untouched.
  if (auto error = check_size(Eye::kLeft, left); !error) return error;
  if (auto error = check_size(Eye::kRight, right); !error) return error;
  rectify_eye(Eye::kLeft, left, left_out);
  rectify_eye(Eye::kRight, right, right_out);
  return {};
}

std::vector<cv::Point2d> Rectifier::rectify_points(Eye eye,
                                                   const std::vector<cv::Point2d>& raw_px) const {
  if (raw_px.empty()) return {};
  const bool left = eye == Eye::kLeft;
  std::vector<cv::Point2d> out;
  // More iterations than OpenCV's default 5 so strong distortion still inverts to ~1e-3 px.
  const cv::TermCriteria criteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 50, 1e-10);
  cv::undistortPoints(raw_px, out, cv::Mat(left ? calib_.k1 : calib_.k2),
                      distortion_mat(left ? calib_.d1 : calib_.d2),
                      cv::Mat(left ? calib_.r1 : calib_.r2), cv::Mat(left ? calib_.p1 : calib_.p2),
                      criteria);
  return out;
}

cv::Point2d Rectifier::rectify_point(Eye eye, cv::Point2d raw_px) const {
  return rectify_points(eye, {raw_px}).front();
}

cv::Point2d Rectifier::unrectify_point(Eye eye, cv::Point2d rectified_px) const {
  const bool left = eye == Eye::kLeft;
  const cv::Matx34d& p = left ? calib_.p1 : calib_.p2;
  const cv::Matx33d& rect = left ? calib_.r1 : calib_.r2;
  // Normalised ray in the rectified camera, rotated back into the raw camera.
  const cv::Vec3d ray_rect((rectified_px.x - p(0, 2)) / p(0, 0),
                           (rectified_px.y - p(1, 2)) / p(1, 1), 1.0);
  const cv::Vec3d ray_raw = rect.t() * ray_rect;
  std::vector<cv::Point3d> object{{ray_raw[0], ray_raw[1], ray_raw[2]}};
  std::vector<cv::Point2d> image;
  cv::projectPoints(object, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0),
                    cv::Mat(left ? calib_.k1 : calib_.k2),
                    distortion_mat(left ? calib_.d1 : calib_.d2), image);
  return image.front();
}

}  // namespace stereoball::stereo
