#include "simulator/core/sim_params.hpp"

#include <string>

namespace stereoball::params {

/// A 3-vector is written as a list of three numbers (x, y, z).
template <>
struct Codec<simulator::Vec3d> {
  static constexpr Kind kKind = Kind::kList;
  static constexpr std::size_t kSize = 3;
  static constexpr bool kWhole = false;
  static Value to(const simulator::Vec3d& v) { return std::vector<double>{v.x, v.y, v.z}; }
  static simulator::Vec3d from(const Value& v) {
    const auto& d = std::get<std::vector<double>>(v);
    return {d.at(0), d.at(1), d.at(2)};
  }
};

}  // namespace stereoball::params

namespace stereoball::simulator {
namespace {

using params::at;
using params::list;
using params::number;
using P = SimParams;
using Fields = std::vector<params::Field<P>>;

// The defaults of one eye (the two eyes of the simulated rig differ slightly).
struct EyeDefaults {
  double hfov_deg, fy_over_fx, cx_offset_px, cy_offset_px;
  std::array<double, 5> distortion;
  double gain;
};

Fields eye_fields(const std::string& name, EyeParams P::*eye, const EyeDefaults& d) {
  const std::string k = name + ".";
  return {
      number(k + "hfov_deg", at(eye, &EyeParams::hfov_deg), d.hfov_deg, {20.0, 120.0}, "deg",
             "horizontal field of view of the pinhole part"),
      number(k + "fy_over_fx", at(eye, &EyeParams::fy_over_fx), d.fy_over_fx, {0.8, 1.25}, "",
             "pixel aspect ratio fy / fx"),
      number(k + "cx_offset_px", at(eye, &EyeParams::cx_offset_px), d.cx_offset_px, {-50.0, 50.0},
             "px", "principal point offset from the image centre"),
      number(k + "cy_offset_px", at(eye, &EyeParams::cy_offset_px), d.cy_offset_px, {-50.0, 50.0},
             "px", "principal point offset from the image centre"),
      list(k + "distortion", at(eye, &EyeParams::distortion), d.distortion, {-0.5, 0.5}, "",
           "k1 k2 p1 p2 k3 (OpenCV order); p1, p2 in [-0.05, 0.05]"),
      number(k + "gain", at(eye, &EyeParams::gain), d.gain, {0.1, 10.0}, "",
             "sensor gain of this eye relative to nominal"),
  };
}

Fields rig_fields() {
  auto rig = [](auto member) { return at(&P::rig, member); };
  return {
      number("rig.baseline_m", rig(&RigParams::baseline_m), 0.12, {0.01, 2.0}, "m",
             "ideal distance between the optical centres"),
      number("rig.height_m", rig(&RigParams::height_m), 0.30, {0.05, 3.0}, "m",
             "optical centres above the floor"),
      number("rig.forward_m", rig(&RigParams::forward_m), 0.10, {-1.0, 1.0}, "m",
             "optical centres ahead of the robot centre"),
      number("rig.tilt_rad", rig(&RigParams::tilt_rad), 0.20, {-1.0, 1.2}, "rad",
             "downward pitch of the rig (positive = down)"),
      list("rig.right_rotation_error_rad", rig(&RigParams::right_rotation_error_rad),
           {0.004, -0.006, 0.003}, {-0.1, 0.1}, "rad", "right camera mis-rotation (x, y, z)"),
      list("rig.right_offset_error_m", rig(&RigParams::right_offset_error_m), {0.0, 0.002, -0.0015},
           {-0.05, 0.05}, "m", "right camera mis-placement (x, y, z)"),
      number("rig.rectify_alpha", rig(&RigParams::rectify_alpha), 0.0, {-1.0, 1.0}, "",
             "cv::stereoRectify alpha of the published calibration (0 = only valid pixels)"),
  };
}

Fields robot_fields() {
  auto robot = [](auto member) { return at(&P::robot, member); };
  return {
      number("robot.max_linear_mps", robot(&RobotParams::max_linear_mps), 1.0, {0.0, 10.0}, "m/s",
             "forward speed limit"),
      number("robot.max_angular_radps", robot(&RobotParams::max_angular_radps), 2.0, {0.0, 20.0},
             "rad/s", "yaw rate limit"),
      number("robot.max_linear_accel_mps2", robot(&RobotParams::max_linear_accel_mps2), 1.5,
             {0.01, 100.0}, "m/s^2", "forward acceleration limit"),
      number("robot.max_angular_accel_radps2", robot(&RobotParams::max_angular_accel_radps2), 6.0,
             {0.01, 200.0}, "rad/s^2", "yaw acceleration limit"),
      number("robot.max_linear_brake_mps2", robot(&RobotParams::max_linear_brake_mps2), 4.0,
             {0.01, 100.0}, "m/s^2", "deceleration limit while the speed drops (stop, slow down)"),
      number("robot.max_angular_brake_radps2", robot(&RobotParams::max_angular_brake_radps2), 16.0,
             {0.01, 400.0}, "rad/s^2", "same for the yaw rate"),
      number("robot.command_timeout_ns", robot(&RobotParams::command_timeout_ns), 300'000'000,
             {1, 60'000'000'000}, "ns", "older commands stop the base"),
      number("robot.radius_m", robot(&RobotParams::radius_m), 0.20, {0.0, 2.0}, "m",
             "footprint radius (walls, ball contact)"),
  };
}

Fields ball_and_sensor_fields() {
  return {
      number("ball.rolling_decel_mps2", at(&P::ball, &BallPhysicsParams::rolling_decel_mps2), 0.12,
             {0.0, 10.0}, "m/s^2", "constant deceleration of a rolling ball"),
      number("ball.restitution", at(&P::ball, &BallPhysicsParams::restitution), 0.7, {0.0, 1.0}, "",
             "fraction of normal speed kept after a bounce"),
      number("ball.physics_step_s", at(&P::ball, &BallPhysicsParams::physics_step_s), 0.002,
             {1e-4, 0.05}, "s", "integration step of the world"),
      number("sensor.noise_sigma_dn", at(&P::sensor, &SensorParams::noise_sigma_dn), 2.0,
             {0.0, 50.0}, "DN", "Gaussian read noise (0..255 scale)"),
      number("sensor.motion_blur_subframes", at(&P::sensor, &SensorParams::motion_blur_subframes),
             1, {1, 16}, "", ">1 renders that many sub-frames per frame and averages them"),
      number("sensor.shutter_s", at(&P::sensor, &SensorParams::shutter_s), 0.012, {0.0, 1.0}, "s",
             "exposure time spanned by the motion blur (at most one frame period)"),
  };
}

// Tangential distortion is small on any real lens; the shutter fits in one frame period.
Status cross_check(const P& p) {
  for (const auto& [name, eye] : {std::pair{"left", &p.left}, std::pair{"right", &p.right}}) {
    for (int i : {2, 3}) {
      if (!params::Range{-0.05, 0.05}.contains(eye->distortion[i])) {
        return Error{params::out_of_range(std::string(name) + ".distortion", eye->distortion[i],
                                          {-0.05, 0.05}, "", i == 2 ? "p1" : "p2")};
      }
    }
  }
  if (p.sensor.shutter_s > 1.0 / p.frame_rate_hz) {
    return Error{params::out_of_range("sensor.shutter_s", p.sensor.shutter_s,
                                      {0.0, 1.0 / p.frame_rate_hz}, "s", "one frame period")};
  }
  return {};
}

params::FieldTable<P> make_table() {
  params::FieldTable<P> t{
      {
          number("width_px", at(&P::width_px), 640, {64, 4096}, "px",
                 "image width (352x288 as in the paper also works)"),
          number("height_px", at(&P::height_px), 480, {48, 4096}, "px", "image height"),
          number("frame_rate_hz", at(&P::frame_rate_hz), 30.0, {0.1, 1000.0}, "Hz",
                 "stereo frames per simulated second"),
      },
      cross_check};
  for (Fields part :
       {eye_fields("left", &P::left,
                   {62.0, 1.0, 3.2, -2.4, {-0.12, 0.035, 0.0004, -0.0003, 0.0}, 1.0}),
        eye_fields("right", &P::right,
                   {61.4, 1.003, -2.6, 1.8, {-0.105, 0.028, -0.0002, 0.0005, 0.0}, 0.96}),
        rig_fields(), robot_fields(), ball_and_sensor_fields()}) {
    t.fields.insert(t.fields.end(), part.begin(), part.end());
  }
  return t;
}

}  // namespace

SB_PARAMS_TABLE(SimParams, sim_fields, make_table)

}  // namespace stereoball::simulator
