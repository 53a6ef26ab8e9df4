#include "stereo/core/calibration_scaling.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace stereoball::stereo {
namespace {

std::string size_text(cv::Size s) {
  return std::to_string(s.width) + "x" + std::to_string(s.height);
}

}  // namespace

cv::Size scaled_size(cv::Size size, int width_px) {
  if (size.width <= 0 || size.height <= 0 || width_px <= 0) return {};
  const double h = static_cast<double>(size.height) * width_px / size.width;
  return {width_px, std::max(1, static_cast<int>(std::lround(h)))};
}

Result<StereoCalibration> scale_calibration(const StereoCalibration& calib, cv::Size size) {
  if (size.width <= 0 || size.height <= 0) {
    return Error{"cannot scale a calibration to " + size_text(size) + " images"};
  }
  if (auto st = validate_calibration(calib); !st) return Error{st.error()};
  const double sx = static_cast<double>(size.width) / calib.image_size.width;
  const double sy = static_cast<double>(size.height) / calib.image_size.height;
  // cv::resize maps destination pixel centres onto source pixel centres: u' = sx*(u+0.5)-0.5.
  const double ox = 0.5 * (sx - 1.0), oy = 0.5 * (sy - 1.0);
  const cv::Matx33d s(sx, 0, ox, 0, sy, oy, 0, 0, 1);
  StereoCalibration out = calib;
  out.image_size = size;
  out.k1 = s * calib.k1;
  out.k2 = s * calib.k2;
  out.p1 = s * calib.p1;
  out.p2 = s * calib.p2;
  // Q takes (u, v, d, 1) to a homogeneous point; the scaled image has (u', v', d') =
  // (sx u + ox, sy v + oy, sx d). Q' = sx * Q * M^-1 keeps the point and OpenCV's form of Q
  // (Q'(0,0) = 1, Q'(2,3) = the scaled focal length).
  const cv::Matx44d m_inv(1 / sx, 0, 0, -ox / sx, 0, 1 / sy, 0, -oy / sy, 0, 0, 1 / sx, 0, 0, 0, 0,
                          1);
  out.q = sx * (calib.q * m_inv);
  if (auto st = validate_calibration(out); !st) {
    return Error{"calibration scaled to " + size_text(size) + ": " + st.error()};
  }
  return out;
}

}  // namespace stereoball::stereo
