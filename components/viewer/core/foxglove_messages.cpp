#include "viewer/core/foxglove_messages.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "viewer/core/cdr_writer.hpp"

namespace stereoball::viewer::foxglove {
namespace {

struct Rgba {
  double r, g, b, a;
};
constexpr Rgba kGreen{0.1, 0.9, 0.2, 1.0};
constexpr Rgba kOrange{1.0, 0.6, 0.0, 1.0};
constexpr Rgba kCyan{0.0, 0.8, 1.0, 0.8};
constexpr Rgba kBall{1.0, 0.4, 0.0, 0.9};
constexpr Rgba kSpread{1.0, 0.4, 0.0, 0.25};
constexpr Rgba kTruth{0.2, 0.4, 1.0, 0.6};
constexpr Rgba kRobot{0.5, 0.5, 0.55, 0.8};
constexpr Rgba kTransparent{0, 0, 0, 0};
constexpr Rgba kTextBackground{0, 0, 0, 0.6};
constexpr Rgba kWhite{1, 1, 1, 1};

struct Quat {
  double x, y, z, w;
};
constexpr Quat kIdentity{0, 0, 0, 1};

Quat yaw(double rad) {
  return {0, 0, std::sin(rad / 2), std::cos(rad / 2)};
}

void time(CdrWriter& w, int64_t stamp_ns) {
  const int64_t ns = stamp_ns < 0 ? 0 : stamp_ns;
  w.u32(static_cast<uint32_t>(ns / 1'000'000'000));
  w.u32(static_cast<uint32_t>(ns % 1'000'000'000));
}
void color(CdrWriter& w, const Rgba& c) {
  w.f64(c.r);
  w.f64(c.g);
  w.f64(c.b);
  w.f64(c.a);
}
void xy(CdrWriter& w, double x, double y) {
  w.f64(x);
  w.f64(y);
}
void xyz(CdrWriter& w, const Vec3& v) {
  w.f64(v[0]);
  w.f64(v[1]);
  w.f64(v[2]);
}
void pose(CdrWriter& w, const Vec3& position, const Quat& q) {
  xyz(w, position);
  w.f64(q.x);
  w.f64(q.y);
  w.f64(q.z);
  w.f64(q.w);
}

// The parts of a SceneEntity this viewer uses; every other primitive list stays empty.
struct Shape {
  Vec3 position;
  Vec3 size;
  Rgba color;
};
struct Arrow {
  Vec3 position;
  Quat orientation;
  double length_m;
  Rgba color;
};
struct Entity {
  std::string_view frame_id;
  std::string id;
  std::vector<Arrow> arrows;
  std::vector<Shape> cubes;
  std::vector<Shape> spheres;
  std::vector<Vec3> line_strip;
  Rgba line_color = kCyan;
};

void entity(CdrWriter& w, const Entity& e, int64_t stamp_ns) {
  time(w, stamp_ns);
  w.string(e.frame_id);
  w.string(e.id);
  w.i32(0);  // lifetime 0 = until replaced
  w.u32(0);
  w.boolean(false);
  w.sequence_length(0);  // metadata
  w.sequence_length(e.arrows.size());
  for (const auto& a : e.arrows) {
    pose(w, a.position, a.orientation);
    w.f64(a.length_m * 0.7);
    w.f64(0.03);
    w.f64(a.length_m * 0.3);
    w.f64(0.08);
    color(w, a.color);
  }
  for (const auto* shapes : {&e.cubes, &e.spheres}) {
    w.sequence_length(shapes->size());
    for (const auto& s : *shapes) {
      pose(w, s.position, kIdentity);
      xyz(w, s.size);
      color(w, s.color);
    }
  }
  w.sequence_length(0);  // cylinders
  w.sequence_length(e.line_strip.size() >= 2 ? 1 : 0);
  if (e.line_strip.size() >= 2) {
    w.u32(0);  // LINE_STRIP
    pose(w, {0, 0, 0}, kIdentity);
    w.f64(0.01);
    w.boolean(false);
    w.sequence_length(e.line_strip.size());
    for (const auto& p : e.line_strip) xyz(w, p);
    color(w, e.line_color);
    w.sequence_length(0);  // colors
    w.sequence_length(0);  // indices
  }
  w.sequence_length(0);  // triangles
  w.sequence_length(0);  // texts
  w.sequence_length(0);  // models
}

std::vector<Entity> scene_entities(const Scene& scene) {
  std::vector<Entity> out;
  // The robot body: 0.4 m x 0.3 m x 0.15 m around the robot frame's origin.
  out.push_back({kRobotFrame, "robot", {}, {{{0, 0, 0.075}, {0.4, 0.3, 0.15}, kRobot}}, {}, {}});
  if (auto e = scene.estimate()) {
    Entity ball{kCameraFrame, "ball_estimate", {}, {}, {}, {}};
    ball.spheres.push_back({e->position_m, {0.08, 0.08, 0.08}, kBall});
    // The register's 1-sigma spread (at least 2 cm so it stays visible).
    Vec3 spread;
    for (int i = 0; i < 3; ++i) spread[i] = std::max(0.02, 2 * e->sigma_m[i]);
    ball.spheres.push_back({e->position_m, spread, kSpread});
    ball.line_strip.push_back(e->position_m);
    for (const auto& p : e->predictions_m) {
      ball.spheres.push_back({p, {0.04, 0.04, 0.04}, kCyan});
      ball.line_strip.push_back(p);
    }
    out.push_back(std::move(ball));
  }
  Entity reg{kCameraFrame, "register", {}, {}, {}, {}};
  for (const auto& p : scene.register_positions())
    reg.cubes.push_back({p, {0.03, 0.03, 0.03}, kGreen});
  out.push_back(std::move(reg));
  Entity search{kRobotFrame, "search_direction", {}, {}, {}, {}};
  if (scene.track() && scene.track()->state == "searching") {
    const double side = scene.track()->last_seen_side == "right" ? -M_PI / 2 : M_PI / 2;
    search.arrows.push_back({{0, 0, 0.2}, yaw(side), 0.5, kOrange});
  }
  out.push_back(std::move(search));
  Entity truth{kWorldFrame, "ground_truth_ball", {}, {}, {}, {}};
  if (scene.truth() && scene.truth()->ball_present) {
    const double d = 2 * scene.truth()->ball_radius_m;
    truth.spheres.push_back({scene.truth()->ball_world_m, {d, d, d}, kTruth});
  }
  out.push_back(std::move(truth));
  return out;
}

}  // namespace

std::string_view eye_frame(Eye eye) {
  return eye == Eye::kLeft ? "camera" : "camera_right";
}

std::vector<uint8_t> compressed_image(int64_t stamp_ns, Eye eye, std::span<const uint8_t> jpeg) {
  CdrWriter w;
  time(w, stamp_ns);
  w.string(eye_frame(eye));
  w.byte_sequence(jpeg);
  w.string("jpeg");
  return w.take();
}

std::vector<uint8_t> image_annotations(const Detection& d, Eye eye, uint32_t width_px,
                                       double scale) {
  const Circle& detected = eye == Eye::kLeft ? d.left : d.right;
  // Detections are in the camera's pixels; the image may be shown smaller.
  const Circle c{detected.x_px * scale, detected.y_px * scale, detected.radius_px * scale,
                 detected.score};
  const bool present = c.score > 0 && c.radius_px > 0;
  const Rgba outline = d.found ? kGreen : kOrange;
  CdrWriter w;
  time(w, d.capture_stamp_ns);
  w.sequence_length(present ? 1 : 0);
  if (present) {
    time(w, d.capture_stamp_ns);
    xy(w, c.x_px, c.y_px);
    w.f64(2 * c.radius_px);
    w.f64(2);
    color(w, kTransparent);
    color(w, outline);
    w.sequence_length(0);  // metadata
  }
  // Points: the centre, and the epipolar row (where the other eye's centre must lie).
  w.sequence_length(present ? 2 : 0);
  if (present) {
    time(w, d.capture_stamp_ns);
    w.u32(1);  // POINTS
    w.sequence_length(1);
    xy(w, c.x_px, c.y_px);
    color(w, outline);
    w.sequence_length(0);
    color(w, outline);
    w.f64(6);
    w.sequence_length(0);  // metadata
    time(w, d.capture_stamp_ns);
    w.u32(4);  // LINE_LIST
    w.sequence_length(2);
    xy(w, 0, c.y_px);
    xy(w, width_px, c.y_px);
    color(w, kCyan);
    w.sequence_length(0);
    color(w, kTransparent);
    w.f64(1);
    w.sequence_length(0);  // metadata
  }
  char score[32];
  std::snprintf(score, sizeof score, "score %.2f", c.score);
  const std::string text = d.found ? std::string(score) : d.status + ": " + d.reason;
  w.sequence_length(1);
  time(w, d.capture_stamp_ns);
  xy(w, present ? c.x_px + c.radius_px + 4 : 8, present ? c.y_px : 20);
  w.string(text);
  w.f64(14);
  color(w, kWhite);
  color(w, kTextBackground);
  w.sequence_length(0);  // metadata of the text
  w.sequence_length(0);  // metadata of the annotations
  return w.take();
}

std::vector<uint8_t> scene_update(const Scene& scene, int64_t stamp_ns) {
  CdrWriter w;
  w.sequence_length(0);  // deletions: entities are replaced by id
  const auto entities = scene_entities(scene);
  w.sequence_length(entities.size());
  for (const auto& e : entities) entity(w, e, stamp_ns);
  return w.take();
}

std::string plot_json(const Scene& scene) {
  nlohmann::json j = {
      {"track_state", nullptr},   {"distance_m", nullptr},
      {"bearing_rad", nullptr},   {"linear_mps", nullptr},
      {"angular_radps", nullptr}, {"estop_engaged", scene.estop() && scene.estop()->engaged}};
  if (const auto& t = scene.track()) {
    j["track_state"] = t->state;
    j["track_state_code"] = t->state == "following" ? 1 : t->state == "searching" ? 2 : 0;
    j["distance_m"] = t->distance_m;
    j["bearing_rad"] = t->bearing_rad;
    j["ssd"] = t->ssd;
  }
  if (!scene.detections().empty()) {
    const auto& d = scene.detections().back();
    j["detection_found"] = d.found;
    j["score_left"] = d.left.score;
    j["row_residual_px"] = d.row_residual_px;
    j["detector_latency_ms"] = d.latency_ms;
  }
  if (!scene.commands().empty()) {
    j["linear_mps"] = scene.commands().back().linear_mps;
    j["angular_radps"] = scene.commands().back().angular_radps;
  }
  return j.dump();
}

std::string_view plot_json_schema() {
  return R"({"type":"object","title":"stereoball.view.Plot","properties":{)"
         R"("track_state":{"type":["string","null"]},"track_state_code":{"type":"integer"},)"
         R"("distance_m":{"type":["number","null"]},"bearing_rad":{"type":["number","null"]},)"
         R"("ssd":{"type":"number"},"linear_mps":{"type":["number","null"]},)"
         R"("angular_radps":{"type":["number","null"]},"estop_engaged":{"type":"boolean"},)"
         R"("detection_found":{"type":"boolean"},"score_left":{"type":"number"},)"
         R"("row_residual_px":{"type":"number"},"detector_latency_ms":{"type":"number"}}})";
}

std::vector<uint8_t> frame_transforms(const Scene& scene, int64_t stamp_ns) {
  CdrWriter w;
  w.sequence_length(2);
  time(w, stamp_ns);
  w.string(kWorldFrame);
  w.string(kRobotFrame);
  const auto& truth = scene.truth();
  xyz(w, truth ? Vec3{truth->robot_x_m, truth->robot_y_m, 0} : Vec3{0, 0, 0});
  const Quat q = truth ? yaw(truth->robot_yaw_rad) : kIdentity;
  w.f64(q.x);
  w.f64(q.y);
  w.f64(q.z);
  w.f64(q.w);
  time(w, stamp_ns);
  w.string(kRobotFrame);
  w.string(kCameraFrame);
  // Optical frame (x right, y down, z forward) in the robot frame (x forward, y left, z up).
  xyz(w, {0, 0, 0});
  w.f64(-0.5);
  w.f64(0.5);
  w.f64(-0.5);
  w.f64(0.5);
  return w.take();
}

}  // namespace stereoball::viewer::foxglove
