#pragma once
// Exact ray caster of the simulated room, one eye at a time.
// Rays of every (distorted) pixel are computed once; per frame only the robot pose changes.
// Objects are culled per 16x16 tile with a cone test, so the ball costs only where it is.

#include <opencv2/core.hpp>

#include <cstdint>
#include <vector>

#include "simulator/core/rig.hpp"
#include "simulator/core/scenario.hpp"
#include "simulator/core/world.hpp"

namespace stereoball::simulator {

/// Renders BGR8 images of a scenario's room as seen by the rig's cameras.
class Renderer {
 public:
  /// Precomputes ray tables and tile cones for both eyes; scenario must be valid.
  Renderer(const StereoRig& rig, const Scenario& scenario, double left_gain, double right_gain);

  /// Renders one eye for the robot pose, ball and lighting into out (CV_8UC3, reallocated
  /// only if its size or type differ). No noise: see Sensor. The left and the right eye may
  /// render at the same time on two threads; one eye must not render twice at once.
  void render(Eye eye, const RobotState& robot, const BallState& ball, const LightKey& light,
              cv::Mat& out);

 private:
  struct Ray {
    float x, y, z;  // unit direction in the robot frame
  };
  struct Tile {
    int x0, y0, x1, y1;
    Vec3f axis;                // robot frame
    float cos_half, sin_half;  // half-angle of the cone holding every ray of the tile
  };
  struct EyeTables {
    std::vector<Ray> rays;
    std::vector<Tile> tiles;
    Vec3d origin_robot_m;
    float gain = 1.0f;
  };
  struct Box {
    Vec3f lo, hi, albedo;
  };
  struct Disc {
    Vec3f c, n, albedo, rim;
    float r2, inner_r2;
  };
  struct Sphere {
    Vec3f c, albedo;
    float r, r2;
  };
  struct Bound {
    Vec3d centre_m;
    double radius_m;
  };
  struct ObjCone {
    Vec3f u;  // robot frame, from the camera toward the object's bounding sphere
    float cos_a = 1.0f, sin_a = 0.0f;
    bool always = false;  // camera inside the bounding sphere
  };
  struct FrameSetup {
    float c = 1.0f, s = 0.0f;  // robot yaw
    Vec3f o;                   // camera origin, world
    Vec3f light;               // toward the light, world
    float ambient = 0.0f, sun = 0.0f, scale = 1.0f;
    float diff_floor = 0.0f, diff_wall[4] = {}, diff_box[3][2] = {};
    bool ball = false;
    Vec3f ball_c;
    float ball_r = 0.0f, ball_r2 = 0.0f;
    float ball_rt[9] = {};       // ball-from-world rotation for the texture
    std::vector<ObjCone> cones;  // boxes, discs, then spheres
    ObjCone ball_cone, shadow_cone;
  };

  // Per-frame state and per-tile scratch of one eye: the two eyes never share any, so both
  // can render at once (on two threads of the caller).
  struct EyeWork {
    FrameSetup frame;
    std::vector<uint16_t> cand_boxes, cand_discs, cand_spheres;
    bool cand_ball = false, cand_shadow = false;
  };

  static ObjCone make_cone(const Vec3d& centre_m, double radius_m, const Vec3d& o_world, double c,
                           double s);
  static bool hits(const Tile& t, const ObjCone& k);
  void setup_frame(const EyeTables& eye, const RobotState& robot, const BallState& ball,
                   const LightKey& light, FrameSetup& f) const;

  void build_eye(Eye eye, const StereoRig& rig, double gain);
  void build_scene(const Scenario& s);
  void cull(const Tile& tile, EyeWork& w) const;
  void render_tile(const EyeTables& eye, const EyeWork& w, const Tile& tile, cv::Mat& out) const;
  Vec3f floor_albedo(float x_m, float y_m) const;
  const Vec3f& ball_albedo(const Vec3f& n_ball) const;

  int width_, height_;
  EyeTables eyes_[2];
  RoomSpec room_;
  Vec3d sun_dir_;  // world, pointing toward the light
  std::vector<Box> boxes_;
  std::vector<Disc> discs_;
  std::vector<Sphere> spheres_;
  std::vector<Bound> bounds_;  // boxes, discs, then spheres
  Vec3f ball_a_, ball_b_;
  BallPattern ball_pattern_ = BallPattern::kFootball;
  EyeWork work_[2];  // left, right
};

}  // namespace stereoball::simulator
