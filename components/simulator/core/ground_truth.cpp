#include "simulator/core/ground_truth.hpp"

#include <algorithm>
#include <cmath>

namespace stereoball::simulator {
namespace {

bool inside(const Point2& p, int w, int h) {
  return p.x >= -0.5 && p.y >= -0.5 && p.x <= w - 0.5 && p.y <= h - 0.5;
}

Point2 project_rectified(const cv::Matx34d& p, const Vec3d& x) {
  const cv::Vec3d h = p * cv::Vec4d(x.x, x.y, x.z, 1.0);
  return {h[0] / h[2], h[1] / h[2]};
}

bool visible(const StereoRig& rig, Eye eye, const Vec3d& cam, const Point2& rect_px) {
  if (cam.z <= 1e-3) return false;
  const int w = rig.width_px(), h = rig.height_px();
  return inside(project_raw(rig.intrinsics(eye), cam), w, h) && inside(rect_px, w, h);
}

Vec3d camera_centre_world(const StereoRig& rig, Eye eye, const RobotState& robot) {
  return Vec3d{robot.x_m, robot.y_m, 0.0} + Mat3::rot_z(robot.yaw_rad) * rig.pose(eye).position_m;
}

// Whether the disc of radius_px around px lies inside the w x h image.
bool disc_inside(const Point2& px, double radius_px, int w, int h) {
  return px.x - radius_px >= 0.0 && px.y - radius_px >= 0.0 && px.x + radius_px <= w - 1.0 &&
         px.y + radius_px <= h - 1.0;
}

bool blocked(const Occluders& occluders, const Vec3d& a, const Vec3d& b) {
  return segment_blocked(occluders.boxes, a, b) || segment_blocked(occluders.spheres, a, b);
}

// Whether the lines of sight from camera to four points just inside the ball's rim are clear.
bool rim_unblocked(const Occluders& occluders, const Vec3d& camera, const Vec3d& ball,
                   double radius_m) {
  const Vec3d u = (ball - camera).normalized();
  Vec3d side{-u.y, u.x, 0.0};  // horizontal, across the line of sight
  if (side.norm() < 1e-9) side = {1.0, 0.0, 0.0};
  side = side.normalized();
  const Vec3d up{u.y * side.z - u.z * side.y, u.z * side.x - u.x * side.z,
                 u.x * side.y - u.y * side.x};
  const double r = 0.95 * radius_m;
  for (const Vec3d& e : {side, side * -1.0, up, up * -1.0})
    if (blocked(occluders, camera, ball + e * r)) return false;
  return true;
}

}  // namespace

bool segment_blocked(const std::vector<SolidBox>& boxes, const Vec3d& a, const Vec3d& b) {
  const Vec3d d = b - a;
  for (const SolidBox& box : boxes) {
    // Slab test restricted to the segment's parameter range (0, 1).
    double t0 = 0.0, t1 = 1.0;
    const double o[3] = {a.x, a.y, a.z}, dv[3] = {d.x, d.y, d.z};
    const double lo[3] = {box.lo.x, box.lo.y, box.lo.z}, hi[3] = {box.hi.x, box.hi.y, box.hi.z};
    bool hit = true;
    for (int i = 0; i < 3 && hit; ++i) {
      if (std::abs(dv[i]) < 1e-12) {
        hit = o[i] > lo[i] && o[i] < hi[i];
        continue;
      }
      double ta = (lo[i] - o[i]) / dv[i], tb = (hi[i] - o[i]) / dv[i];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
      hit = t0 < t1;
    }
    if (hit) return true;
  }
  return false;
}

bool segment_blocked(const std::vector<SphereSpec>& spheres, const Vec3d& a, const Vec3d& b) {
  const Vec3d d = b - a;
  const double length2 = d.dot(d);
  for (const SphereSpec& s : spheres) {
    // The segment's point closest to the centre decides.
    const double t = length2 > 0.0 ? std::clamp((s.center_m - a).dot(d) / length2, 0.0, 1.0) : 0.0;
    const Vec3d closest = a + d * t;
    if ((closest - s.center_m).norm() < s.radius_m) return true;
  }
  return false;
}

Occluders occluders_of(const Scenario& s) {
  return {solid_boxes(s), s.spheres};
}

Vec3d world_to_camera(const StereoRig& rig, Eye eye, const RobotState& robot,
                      const Vec3d& p_world) {
  const Mat3 rz = Mat3::rot_z(robot.yaw_rad);
  const Vec3d p_robot = rz.transposed() * (p_world - Vec3d{robot.x_m, robot.y_m, 0.0});
  const CameraPose& pose = rig.pose(eye);
  return pose.r_robot_from_cam.transposed() * (p_robot - pose.position_m);
}

GroundTruth make_ground_truth(const StereoRig& rig, const RobotState& robot, const BallState& ball,
                              uint64_t frame_seq, int64_t sim_time_ns, const Occluders& occluders) {
  GroundTruth g;
  g.frame_seq = frame_seq;
  g.sim_time_s = sim_time_ns * 1e-9;
  g.robot = robot;
  g.ball_present = ball.present;
  if (!ball.present) return g;
  g.ball_radius_m = ball.radius_m;
  g.ball_world_m = ball.position_m;
  const stereo::StereoCalibration& c = rig.calibration();
  const Vec3d left = world_to_camera(rig, Eye::kLeft, robot, ball.position_m);
  const Vec3d right = world_to_camera(rig, Eye::kRight, robot, ball.position_m);
  const cv::Vec3d rect = c.r1 * cv::Vec3d(left.x, left.y, left.z);
  g.ball_camera_m = {rect[0], rect[1], rect[2]};
  g.ball_left_px = project_rectified(c.p1, g.ball_camera_m);
  // P2 maps points given in the rectified LEFT frame into the rectified right image.
  g.ball_right_px = project_rectified(c.p2, g.ball_camera_m);
  g.ball_visible_left =
      rect[2] > 1e-3 && visible(rig, Eye::kLeft, left, g.ball_left_px) &&
      !blocked(occluders, camera_centre_world(rig, Eye::kLeft, robot), ball.position_m);
  g.ball_visible_right =
      rect[2] > 1e-3 && visible(rig, Eye::kRight, right, g.ball_right_px) &&
      !blocked(occluders, camera_centre_world(rig, Eye::kRight, robot), ball.position_m);
  const double z = rect[2];
  if (z > ball.radius_m) {
    const int w = rig.width_px(), h = rig.height_px();
    const double radius_px =
        1.1 * c.p1(0, 0) * ball.radius_m / std::sqrt(z * z - ball.radius_m * ball.radius_m);
    g.ball_fully_visible_left =
        g.ball_visible_left && disc_inside(g.ball_left_px, radius_px, w, h) &&
        rim_unblocked(occluders, camera_centre_world(rig, Eye::kLeft, robot), ball.position_m,
                      ball.radius_m);
    g.ball_fully_visible_right =
        g.ball_visible_right && disc_inside(g.ball_right_px, radius_px, w, h) &&
        rim_unblocked(occluders, camera_centre_world(rig, Eye::kRight, robot), ball.position_m,
                      ball.radius_m);
  }
  return g;
}

}  // namespace stereoball::simulator
