#include "viewer/core/scene.hpp"

#include <algorithm>
#include <cmath>

namespace stereoball::viewer {
namespace {

nlohmann::json vec(const Vec3& v) {
  return {v[0], v[1], v[2]};
}

nlohmann::json circle(const Circle& c) {
  return {{"x_px", c.x_px}, {"y_px", c.y_px}, {"radius_px", c.radius_px}, {"score", c.score}};
}

std::string health_key(const Health& h) {
  return h.component + "@" + h.host + ":" + std::to_string(h.pid);
}

}  // namespace

Status SceneParams::validate() const {
  if (register_size < 2 || register_size > 50) return Error{"register_size must be in 2..50"};
  if (recent_detections < 1 || recent_detections > 256)
    return Error{"recent_detections must be 1..256"};
  if (command_window_ns <= 0) return Error{"command_window_ns must be > 0"};
  if (max_commands < 1) return Error{"max_commands must be >= 1"};
  if (max_plotted_commands < 2) return Error{"max_plotted_commands must be >= 2"};
  if (health_stale_ns <= 0) return Error{"health_stale_ns must be > 0"};
  for (double h : prediction_horizons_s)
    if (!(h > 0 && h <= 10)) return Error{"prediction_horizons_s must each be in (0, 10] s"};
  return {};
}

Scene::Scene(const SceneParams& params) : params_(params) {}

void Scene::apply(const Detection& d) {
  detections_.push_back(d);
  while (detections_.size() > params_.recent_detections) detections_.pop_front();
  ++version_;
}

void Scene::apply(const Track& t) {
  if (t.accepted && t.position_valid) {
    register_.push_back(t.position_m);
    while (register_.size() > params_.register_size) register_.pop_front();
  }
  // Back to idle means the tracker restarted its start-up: its register is empty again.
  if (t.state == "idle" && !t.accepted) register_.clear();
  track_ = t;
  ++version_;
}

void Scene::apply(const Command& c) {
  commands_.push_back(c);
  // Commands arrive in stamp order from one controller; drop what left the window.
  while (!commands_.empty() &&
         (commands_.size() > params_.max_commands ||
          commands_.front().stamp_ns < c.stamp_ns - params_.command_window_ns))
    commands_.pop_front();
  ++version_;
}

void Scene::apply(const Estop& e) {
  estop_ = e;
  ++version_;
}

void Scene::apply(const Truth& t) {
  truth_ = t;
  ++version_;
}

void Scene::apply(const Health& h) {
  health_[health_key(h)] = h;
  ++version_;
}

std::optional<Detection> Scene::detection_for(uint64_t frame_seq) const {
  for (auto it = detections_.rbegin(); it != detections_.rend(); ++it)
    if (it->frame_seq == frame_seq) return *it;
  return std::nullopt;
}

std::optional<Estimate> Scene::estimate() const {
  if (!track_ || !track_->position_valid) return std::nullopt;
  Estimate e;
  e.position_m = track_->position_m;
  if (register_.size() >= 2) {
    Vec3 mean{};
    for (const auto& p : register_)
      for (int i = 0; i < 3; ++i) mean[i] += p[i] / static_cast<double>(register_.size());
    for (const auto& p : register_)
      for (int i = 0; i < 3; ++i)
        e.sigma_m[i] += (p[i] - mean[i]) * (p[i] - mean[i]) / (register_.size() - 1.0);
    for (double& s : e.sigma_m) s = std::sqrt(s);
  }
  for (double h : params_.prediction_horizons_s) {
    Vec3 p;
    for (int i = 0; i < 3; ++i) p[i] = track_->position_m[i] + track_->velocity_mps[i] * h;
    e.predictions_m.push_back(p);
  }
  return e;
}

nlohmann::json to_json(const Detection& d) {
  return {{"frame_seq", d.frame_seq},
          {"capture_stamp_ns", d.capture_stamp_ns},
          {"found", d.found},
          {"status", d.status},
          {"reason", d.reason},
          {"left", circle(d.left)},
          {"right", circle(d.right)},
          {"row_residual_px", d.row_residual_px},
          {"position_m", vec(d.position_m)},
          {"candidates_left", d.candidates_left},
          {"candidates_right", d.candidates_right},
          {"processing_ms", d.processing_ms},
          {"latency_ms", d.latency_ms}};
}

nlohmann::json to_json(const Track& t) {
  return {{"frame_seq", t.frame_seq},
          {"capture_stamp_ns", t.capture_stamp_ns},
          {"state", t.state},
          {"verdict", t.verdict},
          {"reason", t.reason},
          {"accepted", t.accepted},
          {"position_valid", t.position_valid},
          {"position_m", vec(t.position_m)},
          {"velocity_mps", vec(t.velocity_mps)},
          {"bearing_rad", t.bearing_rad},
          {"distance_m", t.distance_m},
          {"last_seen_side", t.last_seen_side},
          {"ssd", t.ssd},
          {"latency_ms", t.latency_ms}};
}

nlohmann::json Scene::to_json(int64_t now_ns) const {
  nlohmann::json j = {{"type", "scene"}, {"version", version_}, {"now_ns", now_ns}};
  j["detections"] = nlohmann::json::array();
  for (const auto& d : detections_) j["detections"].push_back(viewer::to_json(d));
  j["track"] = track_ ? viewer::to_json(*track_) : nlohmann::json(nullptr);
  j["register_m"] = nlohmann::json::array();
  for (const auto& p : register_) j["register_m"].push_back(vec(p));
  if (auto e = estimate()) {
    nlohmann::json predictions = nlohmann::json::array();
    for (const auto& p : e->predictions_m) predictions.push_back(vec(p));
    j["estimate"] = {{"position_m", vec(e->position_m)},
                     {"sigma_m", vec(e->sigma_m)},
                     {"horizons_s", params_.prediction_horizons_s},
                     {"predictions_m", predictions}};
  } else {
    j["estimate"] = nullptr;
  }
  // Search direction: the side the tracker turns to while searching.
  j["search_side"] = track_ && track_->state == "searching" ? track_->last_seen_side : "";
  j["commands"] = nlohmann::json::array();
  // Thinned evenly (the newest always kept): a 20 s plot needs no more points than pixels.
  const size_t n = commands_.size();
  const size_t step =
      std::max<size_t>(1, (n + params_.max_plotted_commands - 1) / params_.max_plotted_commands);
  for (size_t i = n == 0 ? 0 : (n - 1) % step; i < n; i += step) {
    const auto& c = commands_[i];
    j["commands"].push_back({c.stamp_ns, c.linear_mps, c.angular_radps});
  }
  j["estop"] = estop_ ? nlohmann::json{{"engaged", estop_->engaged},
                                       {"reason", estop_->reason},
                                       {"stamp_ns", estop_->stamp_ns}}
                      : nlohmann::json(nullptr);
  if (truth_) {
    j["truth"] = {{"frame_seq", truth_->frame_seq},
                  {"ball_present", truth_->ball_present},
                  {"ball_radius_m", truth_->ball_radius_m},
                  {"ball_camera_m", vec(truth_->ball_camera_m)},
                  {"ball_world_m", vec(truth_->ball_world_m)},
                  {"robot", {truth_->robot_x_m, truth_->robot_y_m, truth_->robot_yaw_rad}}};
  } else {
    j["truth"] = nullptr;
  }
  j["nodes"] = nlohmann::json::array();
  for (const auto& [key, h] : health_) {
    nlohmann::json rates = nlohmann::json::array();
    for (const auto& r : h.rates)
      rates.push_back({{"topic", r.topic}, {"rate_hz", r.rate_hz}, {"dropped", r.dropped}});
    j["nodes"].push_back({{"component", h.component},
                          {"host", h.host},
                          {"pid", h.pid},
                          {"healthy", h.healthy},
                          {"stale", now_ns - h.stamp_ns > params_.health_stale_ns},
                          {"age_s", (now_ns - h.stamp_ns) / 1e9},
                          {"state", h.state},
                          {"rates", rates},
                          {"errors", h.errors},
                          {"last_error", h.last_error}});
  }
  return j;
}

}  // namespace stereoball::viewer
