#include "stereo/core/calibration.hpp"

#include <opencv2/calib3d.hpp>

#include <cmath>
#include <cstdio>

namespace stereoball::stereo {
namespace {

template <int M, int N>
bool all_finite(const cv::Matx<double, M, N>& m) {
  for (int i = 0; i < M * N; ++i) {
    if (!std::isfinite(m.val[i])) return false;
  }
  return true;
}

bool all_finite(const std::vector<double>& v) {
  for (double x : v) {
    if (!std::isfinite(x)) return false;
  }
  return true;
}

Status check_camera_matrix(const cv::Matx33d& k, const char* name) {
  if (!all_finite(k)) return Error{std::string(name) + ": not finite"};
  if (k(0, 0) <= 0.0 || k(1, 1) <= 0.0)
    return Error{std::string(name) + ": focal lengths must be > 0"};
  if (k(2, 0) != 0.0 || k(2, 1) != 0.0 || k(2, 2) != 1.0) {
    return Error{std::string(name) + ": last row must be [0 0 1]"};
  }
  return {};
}

Status check_distortion(const std::vector<double>& d, const char* name) {
  if (!is_valid_distortion_size(d.size())) {
    return Error{std::string(name) + ": " + std::to_string(d.size()) +
                 " coefficients, expected 0, 4, 5, 8, 12 or 14"};
  }
  if (!all_finite(d)) return Error{std::string(name) + ": not finite"};
  return {};
}

cv::Mat distortion_mat(const std::vector<double>& d) {
  if (d.empty()) return cv::Mat::zeros(1, 5, CV_64F);
  return cv::Mat(d, true).reshape(1, 1);
}

}  // namespace

bool is_valid_distortion_size(std::size_t n) {
  return n == 0 || n == 4 || n == 5 || n == 8 || n == 12 || n == 14;
}

void rectify_calibration(StereoCalibration& calib, const RectifyOptions& options) {
  cv::Mat r1, r2, p1, p2, q;
  const int flags = options.zero_disparity ? cv::CALIB_ZERO_DISPARITY : 0;
  cv::stereoRectify(cv::Mat(calib.k1), distortion_mat(calib.d1), cv::Mat(calib.k2),
                    distortion_mat(calib.d2), calib.image_size, cv::Mat(calib.r), cv::Mat(calib.t),
                    r1, r2, p1, p2, q, flags, options.alpha);
  calib.r1 = cv::Matx33d(r1);
  calib.r2 = cv::Matx33d(r2);
  calib.p1 = cv::Matx34d(p1);
  calib.p2 = cv::Matx34d(p2);
  calib.q = cv::Matx44d(q);
}

StereoCalibration make_calibration(const CameraModel& left, const CameraModel& right,
                                   const cv::Matx33d& r, const cv::Vec3d& t, cv::Size size,
                                   const RectifyOptions& options) {
  StereoCalibration calib;
  calib.image_size = size;
  calib.k1 = left.k;
  calib.d1 = left.d;
  calib.k2 = right.k;
  calib.d2 = right.d;
  calib.r = r;
  calib.t = t;
  rectify_calibration(calib, options);
  return calib;
}

Status validate_calibration(const StereoCalibration& calib) {
  if (calib.image_size.width <= 0 || calib.image_size.height <= 0) {
    return Error{"image_size: width and height must be > 0, got " +
                 std::to_string(calib.image_size.width) + "x" +
                 std::to_string(calib.image_size.height)};
  }
  if (auto e = check_camera_matrix(calib.k1, "K1"); !e) return e;
  if (auto e = check_distortion(calib.d1, "D1"); !e) return e;
  if (auto e = check_camera_matrix(calib.k2, "K2"); !e) return e;
  if (auto e = check_distortion(calib.d2, "D2"); !e) return e;
  if (!all_finite(calib.r)) return Error{"R: not finite"};
  if (std::abs(cv::determinant(calib.r) - 1.0) > 1e-3) return Error{"R: not a rotation (det != 1)"};
  if (!all_finite(calib.t) || cv::norm(calib.t) <= 0.0)
    return Error{"T: must be finite and non-zero"};
  if (!all_finite(calib.r1)) return Error{"R1: not finite"};
  if (!all_finite(calib.r2)) return Error{"R2: not finite"};
  if (!all_finite(calib.p1) || calib.p1(0, 0) <= 0.0)
    return Error{"P1: must be finite with fx > 0"};
  if (!all_finite(calib.p2) || calib.p2(0, 0) <= 0.0)
    return Error{"P2: must be finite with fx > 0"};
  if (calib.p2(0, 3) == 0.0 || calib.p2(1, 3) != 0.0) {
    return Error{"P2: expected horizontal rectification (P2(0,3) = -f*B != 0, P2(1,3) = 0)"};
  }
  if (!all_finite(calib.q) || calib.q(3, 2) == 0.0)
    return Error{"Q: must be finite with Q(3,2) != 0"};
  return {};
}

Status check_image_size(const StereoCalibration& calib, cv::Size left, cv::Size right) {
  auto text = [](cv::Size s) { return std::to_string(s.width) + "x" + std::to_string(s.height); };
  if (left != calib.image_size) {
    return Error{"left image is " + text(left) + " but the calibration is for " +
                 text(calib.image_size)};
  }
  if (right != calib.image_size) {
    return Error{"right image is " + text(right) + " but the calibration is for " +
                 text(calib.image_size)};
  }
  return {};
}

Status check_camera_order(const StereoCalibration& calib) {
  const double b = baseline_m(calib);
  if (b > 0.0) return {};
  char text[64];
  std::snprintf(text, sizeof text, "%.4f", b);
  return Error{
      std::string("negative baseline (") + text +
      " m): the camera given as right is to the left of the one given as left, so every "
      "disparity comes out negative and no ball can be located; the two cameras are swapped"};
}

StereoCalibration swapped_cameras(const StereoCalibration& calib, const RectifyOptions& options) {
  // x_r = R x_l + T  <=>  x_l = R^T x_r - R^T T.
  const cv::Matx33d rt = calib.r.t();
  return make_calibration({calib.k2, calib.d2}, {calib.k1, calib.d1}, rt, -(rt * calib.t),
                          calib.image_size, options);
}

double focal_px(const StereoCalibration& calib) {
  return calib.p1(0, 0);
}

double baseline_m(const StereoCalibration& calib) {
  return -calib.p2(0, 3) / calib.p2(0, 0);
}

}  // namespace stereoball::stereo
