#include "simulator/core/scenario.hpp"

#include "simulator/core/range_check.hpp"

#include <cmath>

namespace stereoball::simulator {
namespace {

Status check_rgb(const std::string& field, const Rgb& c) {
  if (auto e = check_range(field + ".r", c.r, 0, 255); !e) return e;
  if (auto e = check_range(field + ".g", c.g, 0, 255); !e) return e;
  return check_range(field + ".b", c.b, 0, 255);
}

std::string idx(const char* list, size_t i) {
  return std::string(list) + "[" + std::to_string(i) + "]";
}

bool inside_room(const RoomSpec& r, double x, double y, double margin) {
  return x >= r.x_min_m + margin && x <= r.x_max_m - margin && y >= r.y_min_m + margin &&
         y <= r.y_max_m - margin;
}

Status check_room(const RoomSpec& r) {
  if (auto e = check_range("room.x_min_m", r.x_min_m, -100, 100); !e) return e;
  if (auto e = check_range("room.x_max_m", r.x_max_m, r.x_min_m + 1.0, 100); !e) return e;
  if (auto e = check_range("room.y_min_m", r.y_min_m, -100, 100); !e) return e;
  if (auto e = check_range("room.y_max_m", r.y_max_m, r.y_min_m + 1.0, 100); !e) return e;
  if (auto e = check_range("room.height_m", r.height_m, 1.0, 20); !e) return e;
  if (auto e = check_range("room.tile_m", r.tile_m, 0.05, 5); !e) return e;
  if (auto e = check_range("room.grout_m", r.grout_m, 0.0, r.tile_m / 4); !e) return e;
  for (auto [name, c] : {std::pair{"room.floor_a", r.floor_a},
                         {"room.floor_b", r.floor_b},
                         {"room.grout", r.grout},
                         {"room.wall", r.wall},
                         {"room.baseboard", r.baseboard},
                         {"room.ceiling", r.ceiling}}) {
    if (auto e = check_rgb(name, c); !e) return e;
  }
  return {};
}

Status check_ball(const Scenario& s) {
  const BallSpec& b = *s.ball;
  if (auto e = check_range("ball.radius_m", b.radius_m, 0.01, 1.0); !e) return e;
  if (!inside_room(s.room, b.x_m, b.y_m, b.radius_m)) {
    return Error{"ball.x_m/ball.y_m = (" + std::to_string(b.x_m) + ", " + std::to_string(b.y_m) +
                 ") is not inside the room"};
  }
  if (auto e = check_range("ball.vx_mps", b.vx_mps, -20, 20); !e) return e;
  if (auto e = check_range("ball.vy_mps", b.vy_mps, -20, 20); !e) return e;
  if (auto e = check_rgb("ball.color_a", b.color_a); !e) return e;
  return check_rgb("ball.color_b", b.color_b);
}

Status check_clutter(const Scenario& s) {
  for (size_t i = 0; i < s.boxes.size(); ++i) {
    const BoxSpec& b = s.boxes[i];
    const std::string n = idx("boxes", i);
    if (auto e = check_range(n + ".size_x_m", b.size_x_m, 0.01, 20); !e) return e;
    if (auto e = check_range(n + ".size_y_m", b.size_y_m, 0.01, 20); !e) return e;
    if (auto e = check_range(n + ".size_z_m", b.size_z_m, 0.01, 20); !e) return e;
    if (auto e = check_range(n + ".z_m", b.z_m, 0.0, 20); !e) return e;
    if (!inside_room(s.room, b.x_m, b.y_m, 0.0))
      return Error{n + ".x_m/y_m is not inside the room"};
    if (auto e = check_rgb(n + ".color", b.color); !e) return e;
  }
  for (size_t i = 0; i < s.door_frames.size(); ++i) {
    const DoorFrameSpec& d = s.door_frames[i];
    const std::string n = idx("door_frames", i);
    if (auto e = check_range(n + ".width_m", d.width_m, 0.3, 5); !e) return e;
    if (auto e = check_range(n + ".height_m", d.height_m, 0.5, s.room.height_m); !e) return e;
    if (auto e = check_range(n + ".jamb_m", d.jamb_m, 0.01, 0.5); !e) return e;
    if (auto e = check_range(n + ".depth_m", d.depth_m, 0.01, 1.0); !e) return e;
    if (!inside_room(s.room, d.x_m, d.y_m, -0.01))
      return Error{n + ".x_m/y_m is not inside the room"};
    if (auto e = check_rgb(n + ".color", d.color); !e) return e;
    if (auto e = check_rgb(n + ".door_color", d.door_color); !e) return e;
  }
  for (size_t i = 0; i < s.plates.size(); ++i) {
    const PlateSpec& p = s.plates[i];
    const std::string n = idx("plates", i);
    if (auto e = check_range(n + ".radius_m", p.radius_m, 0.01, 5); !e) return e;
    if (auto e = check_range(n + ".rim_m", p.rim_m, 0.0, p.radius_m); !e) return e;
    if (p.normal.norm() < 1e-6 || !std::isfinite(p.normal.norm())) {
      return Error{n + ".normal must be a non-zero vector"};
    }
    if (!inside_room(s.room, p.center_m.x, p.center_m.y, -0.01)) {
      return Error{n + ".center_m is not inside the room"};
    }
    if (auto e = check_range(n + ".center_m.z", p.center_m.z, 0.0, s.room.height_m); !e) return e;
    if (auto e = check_rgb(n + ".color", p.color); !e) return e;
    if (auto e = check_rgb(n + ".rim_color", p.rim_color); !e) return e;
  }
  for (size_t i = 0; i < s.spheres.size(); ++i) {
    const SphereSpec& p = s.spheres[i];
    const std::string n = idx("spheres", i);
    if (auto e = check_range(n + ".radius_m", p.radius_m, 0.01, 2); !e) return e;
    if (!inside_room(s.room, p.center_m.x, p.center_m.y, p.radius_m))
      return Error{n + ".center_m is not inside the room"};
    if (auto e =
            check_range(n + ".center_m.z", p.center_m.z, p.radius_m, s.room.height_m - p.radius_m);
        !e)
      return e;
    if (auto e = check_rgb(n + ".color", p.color); !e) return e;
  }
  return {};
}

template <typename T>
Status check_times(const char* list, const std::vector<T>& v, double dur) {
  double last = -1.0;
  for (size_t i = 0; i < v.size(); ++i) {
    if (auto e = check_range(idx(list, i) + ".t_s", v[i].t_s, 0.0, dur); !e) return e;
    if (v[i].t_s < last)
      return Error{idx(list, i) + ".t_s must not be earlier than the previous entry"};
    last = v[i].t_s;
  }
  return {};
}

Status check_events(const Scenario& s) {
  if (auto e = check_times("kicks", s.kicks, s.duration_s); !e) return e;
  if (auto e = check_times("lighting", s.lighting, s.duration_s); !e) return e;
  if (auto e = check_times("commands", s.commands, s.duration_s); !e) return e;
  if (!s.kicks.empty() && !s.ball) return Error{"kicks: the scenario has no ball to kick"};
  for (size_t i = 0; i < s.kicks.size(); ++i) {
    if (auto e = check_range(idx("kicks", i) + ".vx_mps", s.kicks[i].vx_mps, -20, 20); !e) return e;
    if (auto e = check_range(idx("kicks", i) + ".vy_mps", s.kicks[i].vy_mps, -20, 20); !e) return e;
  }
  for (size_t i = 0; i < s.lighting.size(); ++i) {
    if (auto e = check_range(idx("lighting", i) + ".ambient", s.lighting[i].ambient, 0, 2); !e)
      return e;
    if (auto e = check_range(idx("lighting", i) + ".sun", s.lighting[i].sun, 0, 2); !e) return e;
    if (auto e = check_range(idx("lighting", i) + ".exposure", s.lighting[i].exposure, 0.05, 5); !e)
      return e;
  }
  for (size_t i = 0; i < s.commands.size(); ++i) {
    if (auto e = check_range(idx("commands", i) + ".linear_mps", s.commands[i].linear_mps, -10, 10);
        !e)
      return e;
    if (auto e = check_range(idx("commands", i) + ".angular_radps", s.commands[i].angular_radps,
                             -20, 20);
        !e)
      return e;
  }
  return {};
}

}  // namespace

Status Scenario::validate() const {
  if (name.empty()) return Error{"name must not be empty"};
  if (auto e = check_range("duration_s", duration_s, 0.01, 86400); !e) return e;
  if (auto e = check_room(room); !e) return e;
  if (!inside_room(room, robot_x_m, robot_y_m, 0.0))
    return Error{"robot.x_m/y_m is not inside the room"};
  if (auto e = check_range("robot.yaw_rad", robot_yaw_rad, -10, 10); !e) return e;
  if (robot_max_angular_radps) {
    if (auto e = check_range("robot.max_angular_radps", *robot_max_angular_radps, 0.01, 20); !e)
      return e;
  }
  if (ball) {
    if (auto e = check_ball(*this); !e) return e;
  }
  if (auto e = check_clutter(*this); !e) return e;
  if (auto e = check_range("sun.azimuth_rad", sun_azimuth_rad, -10, 10); !e) return e;
  if (auto e = check_range("sun.elevation_rad", sun_elevation_rad, 0.1, 1.5707963); !e) return e;
  if (calibration) {
    if (auto e = calibration->validate(); !e) return e;
  }
  return check_events(*this);
}

std::vector<SolidBox> solid_boxes(const Scenario& s) {
  std::vector<SolidBox> out;
  for (const BoxSpec& b : s.boxes) {
    out.push_back({{b.x_m - 0.5 * b.size_x_m, b.y_m - 0.5 * b.size_y_m, b.z_m},
                   {b.x_m + 0.5 * b.size_x_m, b.y_m + 0.5 * b.size_y_m, b.z_m + b.size_z_m},
                   b.color});
  }
  for (const DoorFrameSpec& d : s.door_frames) {
    // Local frame: a = along the opening, b = across (depth); mapped to x/y here.
    auto box = [&](double a0, double a1, double b0, double b1, double z0, double z1, const Rgb& c) {
      if (d.along_x) {
        out.push_back({{d.x_m + a0, d.y_m + b0, z0}, {d.x_m + a1, d.y_m + b1, z1}, c});
      } else {
        out.push_back({{d.x_m + b0, d.y_m + a0, z0}, {d.x_m + b1, d.y_m + a1, z1}, c});
      }
    };
    const double w = 0.5 * d.width_m, j = d.jamb_m, dp = 0.5 * d.depth_m;
    box(-w - j, -w, -dp, dp, 0.0, d.height_m + j, d.color);
    box(w, w + j, -dp, dp, 0.0, d.height_m + j, d.color);
    box(-w, w, -dp, dp, d.height_m, d.height_m + j, d.color);
    box(-w, w, -0.3 * dp, 0.3 * dp, 0.0, d.height_m, d.door_color);
  }
  return out;
}

LightKey lighting_at(const Scenario& s, double t_s) {
  if (s.lighting.empty()) return LightKey{};
  if (t_s <= s.lighting.front().t_s) return s.lighting.front();
  for (size_t i = 1; i < s.lighting.size(); ++i) {
    const LightKey& a = s.lighting[i - 1];
    const LightKey& b = s.lighting[i];
    if (t_s < b.t_s) {
      const double u = (t_s - a.t_s) / (b.t_s - a.t_s);
      return {t_s, a.ambient + u * (b.ambient - a.ambient), a.sun + u * (b.sun - a.sun),
              a.exposure + u * (b.exposure - a.exposure)};
    }
  }
  return s.lighting.back();
}

std::optional<ScriptedCommand> scripted_command_at(const Scenario& s, double t_s) {
  std::optional<ScriptedCommand> out;
  for (const ScriptedCommand& c : s.commands) {
    if (c.t_s > t_s) break;
    out = c;
  }
  return out;
}

}  // namespace stereoball::simulator
