#include "simulator/core/rig.hpp"

#include <cmath>

namespace stereoball::simulator {
namespace {

Mat3 level_camera_in_robot(double tilt_rad) {
  // Camera axes (right, down, forward) for a rig pitched down by tilt_rad.
  const double c = std::cos(tilt_rad), s = std::sin(tilt_rad);
  const Vec3d forward{c, 0.0, -s};
  const Vec3d right{0.0, -1.0, 0.0};
  const Vec3d down = forward.cross(right);
  return Mat3::from_columns(right, down, forward);
}

cv::Matx33d to_cv(const Mat3& m) {
  return cv::Matx33d(m.m[0], m.m[1], m.m[2], m.m[3], m.m[4], m.m[5], m.m[6], m.m[7], m.m[8]);
}

stereo::CameraModel camera_model(const Intrinsics& k) {
  return {cv::Matx33d(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1),
          std::vector<double>(k.dist.begin(), k.dist.end())};
}

stereo::StereoCalibration rectify(int w, int h, const Intrinsics (&k)[2],
                                  const CameraPose (&pose)[2], double alpha) {
  // X_right = R X_left + T, from X_robot = R_l X_left + p_l = R_r X_right + p_r.
  const Mat3 rr_t = pose[1].r_robot_from_cam.transposed();
  const Mat3 r = rr_t * pose[0].r_robot_from_cam;
  const Vec3d t = rr_t * (pose[0].position_m - pose[1].position_m);
  stereo::RectifyOptions options;
  options.alpha = alpha;
  options.zero_disparity = true;
  return stereo::make_calibration(camera_model(k[0]), camera_model(k[1]), to_cv(r),
                                  cv::Vec3d(t.x, t.y, t.z), cv::Size(w, h), options);
}

}  // namespace

StereoRig::StereoRig(const SimParams& p) : width_(p.width_px), height_(p.height_px) {
  k_[0] = make_intrinsics(p.left, p.width_px, p.height_px);
  k_[1] = make_intrinsics(p.right, p.width_px, p.height_px);
  const Mat3 r_level = level_camera_in_robot(p.rig.tilt_rad);
  const Vec3d centre{p.rig.forward_m, 0.0, p.rig.height_m};
  // Lateral axis of the rig = camera x axis (robot -y); left eye sits at camera -x.
  const Vec3d cam_x = r_level * Vec3d{1.0, 0.0, 0.0};
  pose_[0] = {r_level, centre - cam_x * (0.5 * p.rig.baseline_m)};
  const Mat3 r_err = Mat3::rodrigues(p.rig.right_rotation_error_rad);
  pose_[1] = {r_level * r_err,
              centre + cam_x * (0.5 * p.rig.baseline_m) + r_level * p.rig.right_offset_error_m};
  calib_ = rectify(width_, height_, k_, pose_, p.rig.rectify_alpha);
}

}  // namespace stereoball::simulator
