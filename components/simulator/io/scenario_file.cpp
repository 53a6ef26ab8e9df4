#include "simulator/io/scenario_file.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include "common/params/yaml_load.hpp"

namespace stereoball::simulator {
namespace {

// Reads the keys of one YAML map; remembers the first error and rejects unknown keys.
class MapReader {
 public:
  MapReader(const YAML::Node& node, std::string prefix, Status& error)
      : node_(node), prefix_(std::move(prefix)), error_(error) {
    if (!node_.IsMap()) fail_key(prefix_.empty() ? "(top level)" : prefix_, "expected a mapping");
  }

  std::string key(const std::string& k) const { return prefix_.empty() ? k : prefix_ + "." + k; }

  // The child node, or an undefined node if absent.
  YAML::Node child(const std::string& k) {
    used_.insert(k);
    if (!node_.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
    const YAML::Node& n = node_;
    return n[k];
  }

  void opt(const std::string& k, double& out) { scalar(k, out, "a number"); }
  void opt(const std::string& k, bool& out) { scalar(k, out, "true or false"); }
  void opt(const std::string& k, std::string& out) { scalar(k, out, "a string"); }
  void opt(const std::string& k, uint64_t& out) { scalar(k, out, "a non-negative integer"); }

  void opt(const std::string& k, Rgb& out) {
    double v[3] = {out.r, out.g, out.b};
    if (triple(k, v, "[r, g, b] (0..255)")) out = {v[0], v[1], v[2]};
  }
  void opt(const std::string& k, Vec3d& out) {
    double v[3] = {out.x, out.y, out.z};
    if (triple(k, v, "[x, y, z]")) out = {v[0], v[1], v[2]};
  }

  // Reports keys that were never asked for (usually typos).
  void finish() {
    if (!node_.IsMap()) return;
    for (const auto& kv : node_) {
      const std::string k = kv.first.as<std::string>("");
      if (!used_.count(k)) fail_key(key(k), "unknown key");
    }
  }

  void fail_key(const std::string& full_key, const std::string& what) {
    if (error_.ok()) error_ = Error{"key '" + full_key + "': " + what};
  }

 private:
  template <typename T>
  void scalar(const std::string& k, T& out, const char* expected) {
    const YAML::Node n = child(k);
    if (!n.IsDefined() || n.IsNull()) return;
    if (!n.IsScalar() || !YAML::convert<T>::decode(n, out)) {
      fail_key(key(k), std::string("expected ") + expected);
    }
  }

  bool triple(const std::string& k, double (&v)[3], const char* expected) {
    const YAML::Node n = child(k);
    if (!n.IsDefined() || n.IsNull()) return false;
    if (!n.IsSequence() || n.size() != 3) {
      fail_key(key(k), std::string("expected ") + expected);
      return false;
    }
    for (size_t i = 0; i < 3; ++i) {
      if (!n[i].IsScalar() || !YAML::convert<double>::decode(n[i], v[i])) {
        fail_key(key(k), std::string("expected ") + expected);
        return false;
      }
    }
    return true;
  }

  YAML::Node node_;
  std::string prefix_;
  Status& error_;  // the first problem; later ones are not reported
  std::set<std::string> used_;
};

// An optional key naming one of choices; out keeps its value when the key is absent.
template <typename E>
void opt_choice(MapReader& m, const std::string& k, E& out,
                const std::vector<std::pair<std::string, E>>& choices) {
  if (!m.child(k).IsDefined()) return;
  std::string name;
  m.opt(k, name);
  std::string expected;
  for (const auto& [text, value] : choices) {
    if (text == name) {
      out = value;
      return;
    }
    expected += (expected.empty() ? "" : ", ") + text;
  }
  m.fail_key(m.key(k), "expected one of " + expected);
}

void read_room(MapReader& top, RoomSpec& r, Status& err) {
  const YAML::Node n = top.child("room");
  if (!n.IsDefined()) return;
  MapReader m(n, "room", err);
  m.opt("x_min_m", r.x_min_m);
  m.opt("x_max_m", r.x_max_m);
  m.opt("y_min_m", r.y_min_m);
  m.opt("y_max_m", r.y_max_m);
  m.opt("height_m", r.height_m);
  m.opt("tile_m", r.tile_m);
  m.opt("grout_m", r.grout_m);
  m.opt("floor_a", r.floor_a);
  m.opt("floor_b", r.floor_b);
  m.opt("grout", r.grout);
  m.opt("wall", r.wall);
  m.opt("baseboard", r.baseboard);
  m.opt("ceiling", r.ceiling);
  m.opt("plain", r.plain);
  opt_choice(m, "floor_pattern", r.floor_pattern,
             {{"tiles", FloorPattern::kTiles},
              {"planks", FloorPattern::kPlanks},
              {"carpet", FloorPattern::kCarpet}});
  m.finish();
}

void read_robot(MapReader& top, Scenario& s, Status& err) {
  const YAML::Node n = top.child("robot");
  if (!n.IsDefined()) return;
  MapReader m(n, "robot", err);
  m.opt("x_m", s.robot_x_m);
  m.opt("y_m", s.robot_y_m);
  m.opt("yaw_rad", s.robot_yaw_rad);
  if (m.child("max_angular_radps").IsDefined()) {
    double max_angular = 0.0;
    m.opt("max_angular_radps", max_angular);
    s.robot_max_angular_radps = max_angular;
  }
  m.finish();
}

void read_ball(MapReader& top, Scenario& s, Status& err) {
  const YAML::Node n = top.child("ball");
  if (!n.IsDefined() || n.IsNull()) return;
  BallSpec b;
  MapReader m(n, "ball", err);
  m.opt("x_m", b.x_m);
  m.opt("y_m", b.y_m);
  m.opt("vx_mps", b.vx_mps);
  m.opt("vy_mps", b.vy_mps);
  m.opt("radius_m", b.radius_m);
  m.opt("color_a", b.color_a);
  m.opt("color_b", b.color_b);
  opt_choice(m, "pattern", b.pattern,
             {{"football", BallPattern::kFootball},
              {"solid", BallPattern::kSolid},
              {"panels", BallPattern::kPanels},
              {"stripes", BallPattern::kStripes}});
  m.finish();
  s.ball = b;
}

void read_sun(MapReader& top, Scenario& s, Status& err) {
  const YAML::Node n = top.child("sun");
  if (!n.IsDefined()) return;
  MapReader m(n, "sun", err);
  m.opt("azimuth_rad", s.sun_azimuth_rad);
  m.opt("elevation_rad", s.sun_elevation_rad);
  m.finish();
}

// Reads a list of maps: one T per entry, each filled by fill(reader, item).
template <typename T, typename F>
void read_list(MapReader& top, const std::string& name, std::vector<T>& out, Status& err, F fill) {
  const YAML::Node n = top.child(name);
  if (!n.IsDefined() || n.IsNull()) return;
  if (!n.IsSequence()) {
    top.fail_key(top.key(name), "expected a list");
    return;
  }
  for (size_t i = 0; i < n.size(); ++i) {
    T item;
    MapReader m(n[i], top.key(name) + "[" + std::to_string(i) + "]", err);
    fill(m, item);
    m.finish();
    out.push_back(item);
  }
}

void read_lists(MapReader& top, Scenario& s, Status& err) {
  read_list(top, "boxes", s.boxes, err, [](MapReader& m, BoxSpec& b) {
    m.opt("x_m", b.x_m);
    m.opt("y_m", b.y_m);
    m.opt("size_x_m", b.size_x_m);
    m.opt("size_y_m", b.size_y_m);
    m.opt("size_z_m", b.size_z_m);
    m.opt("z_m", b.z_m);
    m.opt("color", b.color);
  });
  read_list(top, "door_frames", s.door_frames, err, [](MapReader& m, DoorFrameSpec& d) {
    m.opt("x_m", d.x_m);
    m.opt("y_m", d.y_m);
    std::string along = d.along_x ? "x" : "y";
    m.opt("along", along);
    if (along != "x" && along != "y") m.fail_key(m.key("along"), "expected x or y");
    d.along_x = along == "x";
    m.opt("width_m", d.width_m);
    m.opt("height_m", d.height_m);
    m.opt("jamb_m", d.jamb_m);
    m.opt("depth_m", d.depth_m);
    m.opt("color", d.color);
    m.opt("door_color", d.door_color);
  });
  read_list(top, "plates", s.plates, err, [](MapReader& m, PlateSpec& p) {
    m.opt("center_m", p.center_m);
    m.opt("normal", p.normal);
    m.opt("radius_m", p.radius_m);
    m.opt("rim_m", p.rim_m);
    m.opt("color", p.color);
    m.opt("rim_color", p.rim_color);
  });
  read_list(top, "spheres", s.spheres, err, [](MapReader& m, SphereSpec& p) {
    m.opt("center_m", p.center_m);
    m.opt("radius_m", p.radius_m);
    m.opt("color", p.color);
  });
  read_list(top, "kicks", s.kicks, err, [](MapReader& m, KickSpec& k) {
    m.opt("t_s", k.t_s);
    m.opt("vx_mps", k.vx_mps);
    m.opt("vy_mps", k.vy_mps);
  });
  read_list(top, "lighting", s.lighting, err, [](MapReader& m, LightKey& l) {
    m.opt("t_s", l.t_s);
    m.opt("ambient", l.ambient);
    m.opt("sun", l.sun);
    m.opt("exposure", l.exposure);
  });
  read_list(top, "commands", s.commands, err, [](MapReader& m, ScriptedCommand& c) {
    m.opt("t_s", c.t_s);
    m.opt("linear_mps", c.linear_mps);
    m.opt("angular_radps", c.angular_radps);
  });
}

constexpr double kDeg = M_PI / 180.0;

// An optional angle given in degrees, stored in radians.
void opt_deg(MapReader& m, const std::string& k, double& out_rad) {
  double deg = out_rad / kDeg;
  m.opt(k, deg);
  out_rad = deg * kDeg;
}

void read_board(MapReader& top, CalibrationBoard& b, Status& err) {
  const YAML::Node n = top.child("board");
  if (!n.IsDefined()) return;
  MapReader m(n, "calibration.board", err);
  const YAML::Node corners = m.child("inner_corners");
  if (corners.IsDefined()) {
    if (!corners.IsSequence() || corners.size() != 2 || !corners[0].IsScalar() ||
        !corners[1].IsScalar() || !YAML::convert<int>::decode(corners[0], b.cols) ||
        !YAML::convert<int>::decode(corners[1], b.rows)) {
      m.fail_key(m.key("inner_corners"), "expected [columns, rows] of inner corners, e.g. [9, 6]");
    }
  }
  m.opt("square_m", b.square_m);
  m.opt("margin_m", b.margin_m);
  m.opt("black_dn", b.black_dn);
  m.opt("white_dn", b.white_dn);
  m.finish();
}

void read_random_poses(MapReader& top, CalibrationScene& c, Status& err) {
  const YAML::Node n = top.child("random_poses");
  if (!n.IsDefined() || n.IsNull()) return;
  BoardPoseRanges r;
  MapReader m(n, "calibration.random_poses", err);
  double count = r.count;
  m.opt("count", count);
  if (count != std::floor(count) || count < 1 || count > 1000)
    m.fail_key(m.key("count"), "expected a whole number in [1, 1000]");
  r.count = static_cast<int>(count);
  m.opt("seed", r.seed);
  m.opt("near_m", r.near_m);
  m.opt("far_m", r.far_m);
  opt_deg(m, "max_tilt_deg", r.max_tilt_rad);
  opt_deg(m, "max_roll_deg", r.max_roll_rad);
  m.opt("hold_s", r.hold_s);
  m.opt("move_s", r.move_s);
  m.finish();
  c.random_poses = r;
}

void read_calibration(MapReader& top, Scenario& s, Status& err) {
  const YAML::Node n = top.child("calibration");
  if (!n.IsDefined() || n.IsNull()) return;
  CalibrationScene c;
  MapReader m(n, "calibration", err);
  read_board(m, c.board, err);
  double skew_ms = c.eye_skew_s * 1e3;
  m.opt("eye_skew_ms", skew_ms);
  c.eye_skew_s = skew_ms * 1e-3;
  m.opt("background_dn", c.background_dn);
  read_list(m, "poses", c.holds, err, [](MapReader& p, BoardHold& h) {
    p.opt("x_m", h.pose.centre_m.x);
    p.opt("y_m", h.pose.centre_m.y);
    p.opt("z_m", h.pose.centre_m.z);
    opt_deg(p, "tilt_x_deg", h.pose.tilt_x_rad);
    opt_deg(p, "tilt_y_deg", h.pose.tilt_y_rad);
    opt_deg(p, "roll_deg", h.pose.roll_rad);
    p.opt("hold_s", h.hold_s);
    p.opt("move_s", h.move_s);
  });
  read_random_poses(m, c, err);
  m.finish();
  s.calibration = c;
}

}  // namespace

Result<Scenario> parse_scenario(const std::string& text, const std::string& source) {
  auto parsed = params::parse_yaml(text, source);
  if (!parsed) return Error{parsed.error()};
  const YAML::Node& root = *parsed;
  Scenario s;
  Status err;
  MapReader top(root, "", err);
  top.opt("name", s.name);
  top.opt("seed", s.seed);
  const bool duration_given = top.child("duration_s").IsDefined();
  top.opt("duration_s", s.duration_s);
  read_room(top, s.room, err);
  read_robot(top, s, err);
  read_ball(top, s, err);
  read_sun(top, s, err);
  read_lists(top, s, err);
  read_calibration(top, s, err);
  top.finish();
  if (!err.ok()) return Error{source + ": " + err.error()};
  // A calibration scene lasts as long as its poses unless the file says otherwise.
  if (s.calibration && !duration_given && s.calibration->validate())
    s.duration_s = s.calibration->duration_s();
  if (auto e = s.validate(); !e) return Error{source + ": " + e.error()};
  return s;
}

Result<Scenario> load_scenario(const std::string& path) {
  std::ifstream in(path);
  if (!in) return Error{path + ": cannot open scenario file"};
  std::ostringstream text;
  text << in.rdbuf();
  return parse_scenario(text.str(), path);
}

Result<Scenario> load_scenario_by_name(const std::string& name_or_path, const std::string& dir) {
  const bool is_path =
      name_or_path.find('/') != std::string::npos ||
      (name_or_path.size() > 5 && name_or_path.compare(name_or_path.size() - 5, 5, ".yaml") == 0);
  if (is_path) return load_scenario(name_or_path);
  std::ifstream probe(dir + "/" + name_or_path + ".yaml");
  if (!probe) {
    return Error{"scenario '" + name_or_path + "': no file " + dir + "/" + name_or_path + ".yaml"};
  }
  return load_scenario(dir + "/" + name_or_path + ".yaml");
}

}  // namespace stereoball::simulator
