#include "simulator/core/renderer.hpp"

#include <algorithm>
#include <cmath>

namespace stereoball::simulator {
namespace {

constexpr int kTilePx = 16;
constexpr float kBaseboardM = 0.10f;
// Football-like texture: patches around the 12 icosahedron vertices.
constexpr float kPatchCos = 0.935f;  // cos(~20.8 deg) angular patch radius
constexpr float kPhi = 1.618034f;

Vec3f rgb_to_vec(const Rgb& c) {
  return {static_cast<float>(c.b), static_cast<float>(c.g), static_cast<float>(c.r)};  // BGR
}

struct PatchDirs {
  Vec3f d[12];
  PatchDirs() {
    int i = 0;
    for (float a : {-1.0f, 1.0f}) {
      for (float b : {-kPhi, kPhi}) {
        d[i++] = Vec3f{0, a, b}.normalized();
        d[i++] = Vec3f{a, b, 0}.normalized();
        d[i++] = Vec3f{b, 0, a}.normalized();
      }
    }
  }
};
const PatchDirs kPatches;

// A value in [0, 1) that looks random per integer cell (floor planks and carpet fibres).
inline float cell_noise(int ix, int iy) {
  uint32_t h = static_cast<uint32_t>(ix) * 0x8da6b343u ^ static_cast<uint32_t>(iy) * 0xd8163841u;
  h ^= h >> 13;
  h *= 0x85ebca6bu;
  h ^= h >> 16;
  return static_cast<float>(h & 0xffffu) * (1.0f / 65536.0f);
}

inline Vec3f mix(const Vec3f& a, const Vec3f& b, float t) {
  return a * (1.0f - t) + b * t;
}

constexpr float kPi = 3.14159265f;
constexpr int kBallPanels = 6;   // longitudinal panels of a panelled ball
constexpr int kBallStripes = 6;  // latitude bands of a striped ball
constexpr float kCarpetCellM = 0.01f;
constexpr float kPlankLengthTiles = 3.0f;  // plank length in tile_m
constexpr float kPlanksPerTile = 4.0f;     // plank width = tile_m / 4

inline void put(uint8_t* px, const Vec3f& albedo, float light) {
  const float b = albedo.x * light + 0.5f, g = albedo.y * light + 0.5f, r = albedo.z * light + 0.5f;
  px[0] = static_cast<uint8_t>(std::min(b, 255.0f));
  px[1] = static_cast<uint8_t>(std::min(g, 255.0f));
  px[2] = static_cast<uint8_t>(std::min(r, 255.0f));
}

}  // namespace

Renderer::Renderer(const StereoRig& rig, const Scenario& scenario, double left_gain,
                   double right_gain)
    : width_(rig.width_px()), height_(rig.height_px()), room_(scenario.room) {
  build_eye(Eye::kLeft, rig, left_gain);
  build_eye(Eye::kRight, rig, right_gain);
  build_scene(scenario);
  const double ce = std::cos(scenario.sun_elevation_rad);
  sun_dir_ = {ce * std::cos(scenario.sun_azimuth_rad), ce * std::sin(scenario.sun_azimuth_rad),
              std::sin(scenario.sun_elevation_rad)};
  const BallSpec ball = scenario.ball.value_or(BallSpec{});
  ball_a_ = rgb_to_vec(ball.color_a);
  ball_b_ = rgb_to_vec(ball.color_b);
  ball_pattern_ = ball.pattern;
  for (EyeWork& w : work_) {
    w.cand_boxes.reserve(boxes_.size());
    w.cand_discs.reserve(discs_.size());
    w.cand_spheres.reserve(spheres_.size());
    w.frame.cones.resize(bounds_.size());
  }
}

void Renderer::build_eye(Eye eye, const StereoRig& rig, double gain) {
  EyeTables& t = eyes_[static_cast<int>(eye)];
  const Intrinsics& k = rig.intrinsics(eye);
  const CameraPose& pose = rig.pose(eye);
  t.origin_robot_m = pose.position_m;
  t.gain = static_cast<float>(gain);
  t.rays.resize(static_cast<size_t>(width_) * height_);
  for (int v = 0; v < height_; ++v) {
    for (int u = 0; u < width_; ++u) {
      const Point2 pd{(u - k.cx) / k.fx, (v - k.cy) / k.fy};
      // Newton always converges for validated distortion; fall back to the distorted point.
      const Point2 p = undistort_normalized(k.dist, pd).value_or(pd);
      const Vec3d d = (pose.r_robot_from_cam * Vec3d{p.x, p.y, 1.0}).normalized();
      t.rays[static_cast<size_t>(v) * width_ + u] = {
          static_cast<float>(d.x), static_cast<float>(d.y), static_cast<float>(d.z)};
    }
  }
  t.tiles.clear();
  for (int y0 = 0; y0 < height_; y0 += kTilePx) {
    for (int x0 = 0; x0 < width_; x0 += kTilePx) {
      Tile tile{x0, y0, std::min(x0 + kTilePx, width_), std::min(y0 + kTilePx, height_), {}, 1, 0};
      Vec3d sum;
      for (int v = tile.y0; v < tile.y1; ++v) {
        for (int u = tile.x0; u < tile.x1; ++u) {
          const Ray& r = t.rays[static_cast<size_t>(v) * width_ + u];
          sum = sum + Vec3d{r.x, r.y, r.z};
        }
      }
      const Vec3d axis = sum.normalized();
      double min_cos = 1.0;
      for (int v = tile.y0; v < tile.y1; ++v) {
        for (int u = tile.x0; u < tile.x1; ++u) {
          const Ray& r = t.rays[static_cast<size_t>(v) * width_ + u];
          min_cos = std::min(min_cos, axis.dot(Vec3d{r.x, r.y, r.z}));
        }
      }
      // Widen slightly so float rounding can never cull a ray that hits.
      const double half = std::acos(std::clamp(min_cos, -1.0, 1.0)) + 1e-3;
      tile.axis = axis.cast<float>();
      tile.cos_half = static_cast<float>(std::cos(half));
      tile.sin_half = static_cast<float>(std::sin(half));
      t.tiles.push_back(tile);
    }
  }
}

void Renderer::build_scene(const Scenario& s) {
  for (const SolidBox& b : solid_boxes(s)) {
    boxes_.push_back({b.lo.cast<float>(), b.hi.cast<float>(), rgb_to_vec(b.color)});
    bounds_.push_back({(b.lo + b.hi) * 0.5, (b.hi - b.lo).norm() * 0.5});
  }
  for (const PlateSpec& p : s.plates) {
    const double inner = p.radius_m - p.rim_m;
    discs_.push_back({p.center_m.cast<float>(), p.normal.normalized().cast<float>(),
                      rgb_to_vec(p.color), rgb_to_vec(p.rim_color),
                      static_cast<float>(p.radius_m * p.radius_m),
                      static_cast<float>(inner * inner)});
    bounds_.push_back({p.center_m, p.radius_m * 1.01});
  }
  for (const SphereSpec& p : s.spheres) {
    const auto r = static_cast<float>(p.radius_m);
    spheres_.push_back({p.center_m.cast<float>(), rgb_to_vec(p.color), r, r * r});
    bounds_.push_back({p.center_m, p.radius_m * 1.01});
  }
}

Renderer::ObjCone Renderer::make_cone(const Vec3d& centre_m, double radius_m, const Vec3d& o_world,
                                      double c, double s) {
  const Vec3d dw = centre_m - o_world;
  const Vec3d dr{c * dw.x + s * dw.y, -s * dw.x + c * dw.y, dw.z};  // world -> robot axes
  const double dist = dr.norm();
  ObjCone k;
  if (dist <= radius_m * 1.001) {
    k.always = true;
    return k;
  }
  const double a = std::asin(radius_m / dist);
  k.u = (dr * (1.0 / dist)).cast<float>();
  k.cos_a = static_cast<float>(std::cos(a));
  k.sin_a = static_cast<float>(std::sin(a));
  return k;
}

bool Renderer::hits(const Tile& t, const ObjCone& k) {
  if (k.always) return true;
  // Angle(u, axis) <= half + a  <=>  cos(angle) >= cos(half + a), valid while half + a < pi.
  const float cos_sum = t.cos_half * k.cos_a - t.sin_half * k.sin_a;
  const float sin_sum = t.sin_half * k.cos_a + t.cos_half * k.sin_a;
  if (cos_sum < 0.0f && sin_sum < 0.0f) return true;  // half + a beyond pi
  return k.u.dot(t.axis) >= cos_sum - 1e-4f;
}

void Renderer::setup_frame(const EyeTables& eye, const RobotState& robot, const BallState& ball,
                           const LightKey& light, FrameSetup& f) const {
  const double c = std::cos(robot.yaw_rad), s = std::sin(robot.yaw_rad);
  f.c = static_cast<float>(c);
  f.s = static_cast<float>(s);
  const Vec3d o =
      Vec3d{robot.x_m, robot.y_m, 0.0} + Mat3::rot_z(robot.yaw_rad) * eye.origin_robot_m;
  f.o = o.cast<float>();
  f.light = sun_dir_.cast<float>();
  f.ambient = static_cast<float>(light.ambient);
  f.sun = static_cast<float>(light.sun);
  f.scale = static_cast<float>(light.exposure) * eye.gain;
  auto diffuse = [&](Vec3d n) {
    return static_cast<float>(light.ambient + light.sun * std::max(0.0, n.dot(sun_dir_)));
  };
  f.diff_floor = diffuse({0, 0, 1});
  f.diff_wall[0] = diffuse({1, 0, 0});   // wall at x_min faces +x
  f.diff_wall[1] = diffuse({-1, 0, 0});  // x_max
  f.diff_wall[2] = diffuse({0, 1, 0});   // y_min
  f.diff_wall[3] = diffuse({0, -1, 0});  // y_max
  for (int a = 0; a < 3; ++a) {
    Vec3d n;
    (a == 0 ? n.x : a == 1 ? n.y : n.z) = 1.0;
    f.diff_box[a][0] = diffuse(n);   // face pointing +axis
    f.diff_box[a][1] = diffuse(-n);  // face pointing -axis
  }
  for (size_t i = 0; i < bounds_.size(); ++i) {
    f.cones[i] = make_cone(bounds_[i].centre_m, bounds_[i].radius_m, o, c, s);
  }
  f.ball = ball.present;
  if (ball.present) {
    f.ball_c = ball.position_m.cast<float>();
    f.ball_r = static_cast<float>(ball.radius_m);
    f.ball_r2 = f.ball_r * f.ball_r;
    const Mat3 rt = ball.orientation.transposed();
    for (int i = 0; i < 9; ++i) f.ball_rt[i] = static_cast<float>(rt.m[i]);
    f.ball_cone = make_cone(ball.position_m, ball.radius_m * 1.01, o, c, s);
    // The shadow is an ellipse around the centre's projection along the light onto the floor.
    const Vec3d sc = ball.position_m - sun_dir_ * (ball.position_m.z / sun_dir_.z);
    f.shadow_cone = make_cone(sc, ball.radius_m / sun_dir_.z * 1.05 + 0.01, o, c, s);
  }
}

void Renderer::cull(const Tile& tile, EyeWork& w) const {
  const FrameSetup& f = w.frame;
  w.cand_boxes.clear();
  w.cand_discs.clear();
  for (size_t i = 0; i < boxes_.size(); ++i) {
    if (hits(tile, f.cones[i])) w.cand_boxes.push_back(static_cast<uint16_t>(i));
  }
  for (size_t i = 0; i < discs_.size(); ++i) {
    if (hits(tile, f.cones[boxes_.size() + i])) w.cand_discs.push_back(static_cast<uint16_t>(i));
  }
  w.cand_spheres.clear();
  for (size_t i = 0; i < spheres_.size(); ++i) {
    if (hits(tile, f.cones[boxes_.size() + discs_.size() + i]))
      w.cand_spheres.push_back(static_cast<uint16_t>(i));
  }
  w.cand_ball = f.ball && hits(tile, f.ball_cone);
  w.cand_shadow = f.ball && hits(tile, f.shadow_cone);
}

void Renderer::render(Eye eye, const RobotState& robot, const BallState& ball,
                      const LightKey& light, cv::Mat& out) {
  out.create(height_, width_, CV_8UC3);
  const EyeTables& t = eyes_[static_cast<int>(eye)];
  EyeWork& w = work_[static_cast<int>(eye)];
  setup_frame(t, robot, ball, light, w.frame);
  for (const Tile& tile : t.tiles) {
    cull(tile, w);
    render_tile(t, w, tile, out);
  }
}

void Renderer::render_tile(const EyeTables& eye, const EyeWork& w, const Tile& tile,
                           cv::Mat& out) const {
  const FrameSetup& f = w.frame;
  enum Hit { kFloor, kCeiling, kWall, kBox, kDisc, kSphere, kBall };
  const float xmin = static_cast<float>(room_.x_min_m), xmax = static_cast<float>(room_.x_max_m);
  const float ymin = static_cast<float>(room_.y_min_m), ymax = static_cast<float>(room_.y_max_m);
  const float zmax = static_cast<float>(room_.height_m);
  const Vec3f wall_c = rgb_to_vec(room_.wall);
  const Vec3f base_c = rgb_to_vec(room_.baseboard), ceil_c = rgb_to_vec(room_.ceiling);
  const Vec3f o = f.o;
  const Vec3f oc = o - f.ball_c;
  const float oc2 = oc.dot(oc) - f.ball_r2;

  for (int v = tile.y0; v < tile.y1; ++v) {
    const Ray* ray = eye.rays.data() + static_cast<size_t>(v) * width_ + tile.x0;
    uint8_t* px = out.ptr<uint8_t>(v) + 3 * tile.x0;
    for (int u = tile.x0; u < tile.x1; ++u, ++ray, px += 3) {
      const Vec3f d{f.c * ray->x - f.s * ray->y, f.s * ray->x + f.c * ray->y, ray->z};
      const float ix = 1.0f / d.x, iy = 1.0f / d.y, iz = 1.0f / d.z;
      // Room: nearest of the x wall, y wall and floor/ceiling planes the ray leaves through.
      float t = ((d.x > 0 ? xmax : xmin) - o.x) * ix;
      Hit hit = kWall;
      int which = d.x > 0 ? 1 : 0;
      const float ty = ((d.y > 0 ? ymax : ymin) - o.y) * iy;
      if (ty < t) t = ty, which = d.y > 0 ? 3 : 2;
      const float tz = ((d.z > 0 ? zmax : 0.0f) - o.z) * iz;
      if (tz < t) t = tz, hit = d.z > 0 ? kCeiling : kFloor;
      int axis = 0;
      for (uint16_t bi : w.cand_boxes) {
        const Box& b = boxes_[bi];
        const float x0 = (b.lo.x - o.x) * ix, x1 = (b.hi.x - o.x) * ix;
        const float y0 = (b.lo.y - o.y) * iy, y1 = (b.hi.y - o.y) * iy;
        const float z0 = (b.lo.z - o.z) * iz, z1 = (b.hi.z - o.z) * iz;
        const float nx = std::min(x0, x1), ny = std::min(y0, y1), nz = std::min(z0, z1);
        const float tn = std::max(nx, std::max(ny, nz));
        const float tf = std::min(std::max(x0, x1), std::min(std::max(y0, y1), std::max(z0, z1)));
        if (tn <= tf && tn > 0.0f && tn < t) {
          t = tn;
          hit = kBox;
          which = bi;
          axis = tn == nx ? 0 : tn == ny ? 1 : 2;
        }
      }
      for (uint16_t di : w.cand_discs) {
        const Disc& c = discs_[di];
        const float den = d.dot(c.n);
        if (std::abs(den) < 1e-6f) continue;
        const float td = (c.c - o).dot(c.n) / den;
        if (td <= 0.0f || td >= t) continue;
        const Vec3f q = o + d * td - c.c;
        if (q.dot(q) < c.r2) t = td, hit = kDisc, which = di;
      }
      for (uint16_t si : w.cand_spheres) {
        const Sphere& sp = spheres_[si];
        const Vec3f so = o - sp.c;
        const float b = so.dot(d);
        const float disc = b * b - (so.dot(so) - sp.r2);
        if (disc < 0.0f) continue;
        const float ts = -b - std::sqrt(disc);
        if (ts > 0.0f && ts < t) t = ts, hit = kSphere, which = si;
      }
      if (w.cand_ball) {
        const float b = oc.dot(d);
        const float disc = b * b - oc2;
        if (disc >= 0.0f) {
          const float tb = -b - std::sqrt(disc);
          if (tb > 0.0f && tb < t) t = tb, hit = kBall;
        }
      }
      const Vec3f p = o + d * t;
      switch (hit) {
        case kFloor: {
          const Vec3f alb = floor_albedo(p.x, p.y);
          float light = f.diff_floor;
          if (w.cand_shadow) {
            const Vec3f q = f.ball_c - p;
            const float proj = q.dot(f.light);
            if (proj > 0.0f && q.dot(q) - proj * proj < f.ball_r2) light = f.ambient;
          }
          put(px, alb, light * f.scale);
          break;
        }
        case kCeiling:
          put(px, ceil_c, f.ambient * f.scale);
          break;
        case kWall:
          put(px, (!room_.plain && p.z < kBaseboardM) ? base_c : wall_c,
              f.diff_wall[which] * f.scale);
          break;
        case kBox: {
          const float comp = axis == 0 ? d.x : axis == 1 ? d.y : d.z;
          put(px, boxes_[which].albedo, f.diff_box[axis][comp > 0 ? 1 : 0] * f.scale);
          break;
        }
        case kDisc: {
          const Disc& c = discs_[which];
          const Vec3f q = p - c.c;
          const float facing = d.dot(c.n) < 0 ? 1.0f : -1.0f;
          const float light = f.ambient + f.sun * std::max(0.0f, facing * c.n.dot(f.light));
          put(px, q.dot(q) > c.inner_r2 ? c.rim : c.albedo, light * f.scale);
          break;
        }
        case kSphere: {
          const Sphere& sp = spheres_[which];
          const Vec3f n = (p - sp.c) * (1.0f / sp.r);
          put(px, sp.albedo, (f.ambient + f.sun * std::max(0.0f, n.dot(f.light))) * f.scale);
          break;
        }
        case kBall: {
          const Vec3f n = (p - f.ball_c) * (1.0f / f.ball_r);
          const float* m = f.ball_rt;
          const Vec3f nb{m[0] * n.x + m[1] * n.y + m[2] * n.z, m[3] * n.x + m[4] * n.y + m[5] * n.z,
                         m[6] * n.x + m[7] * n.y + m[8] * n.z};
          const float light = f.ambient + f.sun * std::max(0.0f, n.dot(f.light));
          put(px, ball_albedo(nb), light * f.scale);
          break;
        }
      }
    }
  }
}

Vec3f Renderer::floor_albedo(float x_m, float y_m) const {
  const Vec3f a = rgb_to_vec(room_.floor_a), b = rgb_to_vec(room_.floor_b);
  if (room_.plain) return a;
  const float tile = static_cast<float>(room_.tile_m), grout = static_cast<float>(room_.grout_m);
  switch (room_.floor_pattern) {
    case FloorPattern::kTiles: {
      const float fu = x_m / tile, fv = y_m / tile;
      const float iu = std::floor(fu), iv = std::floor(fv);
      const float g = grout / tile;
      if (fu - iu < g || fv - iv < g) return rgb_to_vec(room_.grout);
      return ((static_cast<int>(iu) + static_cast<int>(iv)) & 1) ? b : a;
    }
    case FloorPattern::kPlanks: {
      const float width = tile / kPlanksPerTile, length = tile * kPlankLengthTiles;
      const float fv = y_m / width, iv = std::floor(fv);
      const int row = static_cast<int>(iv);
      // Each row's plank ends are shifted by its own fraction of a plank length.
      const float fu = x_m / length + cell_noise(row, 7), iu = std::floor(fu);
      if ((fv - iv) * width < grout || (fu - iu) * length < grout) return rgb_to_vec(room_.grout);
      return mix(a, b, cell_noise(static_cast<int>(iu), row));
    }
    case FloorPattern::kCarpet: {
      const int ix = static_cast<int>(std::floor(x_m / kCarpetCellM));
      const int iy = static_cast<int>(std::floor(y_m / kCarpetCellM));
      return mix(a, b, cell_noise(ix, iy));
    }
  }
  return a;
}

const Vec3f& Renderer::ball_albedo(const Vec3f& nb) const {
  switch (ball_pattern_) {
    case BallPattern::kSolid:
      return ball_a_;
    case BallPattern::kPanels: {
      const int sector =
          static_cast<int>((std::atan2(nb.y, nb.x) + kPi) * (kBallPanels / (2.0f * kPi)));
      return (sector & 1) ? ball_b_ : ball_a_;
    }
    case BallPattern::kStripes: {
      const int band = static_cast<int>((std::clamp(nb.z, -1.0f, 0.9999f) + 1.0f) * 0.5f *
                                        static_cast<float>(kBallStripes));
      return (band & 1) ? ball_b_ : ball_a_;
    }
    case BallPattern::kFootball:
      break;
  }
  for (const Vec3f& pd : kPatches.d)
    if (nb.dot(pd) > kPatchCos) return ball_b_;
  return ball_a_;
}

}  // namespace stereoball::simulator
