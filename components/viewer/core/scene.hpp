#pragma once
// The viewer's picture of the system: latest detection, track, commands over time, e-stop,
// ground truth and every node's health, plus what it derives from them (the five-position
// register, the estimate's spread and the predicted positions). Serialised as one JSON
// object for the page and the Foxglove plot channel. Time is an argument throughout.

#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/util/result.hpp"
#include "viewer/core/view_model.hpp"

namespace stereoball::viewer {

/// How much history the scene keeps and what it predicts.
struct SceneParams {
  size_t register_size = 5;                    ///< positions in the register (the paper: 5)
  size_t recent_detections = 8;                ///< detections kept for matching to images
  int64_t command_window_ns = 20'000'000'000;  ///< commands kept for the time plot
  size_t max_commands = 2000;                  ///< hard bound on the command history
  size_t max_plotted_commands = 300;           ///< commands in the JSON (evenly thinned)
  int64_t health_stale_ns = 3'000'000'000;     ///< a node silent this long shows as stale
  std::vector<double> prediction_horizons_s = {0.5, 1.0, 1.5};  ///< predicted positions
  /// Success, or an error naming the bad field and its allowed range.
  Status validate() const;
};

/// Ball estimate derived from the register: mean position, 1-sigma spread per axis (metres)
/// and positions predicted with the tracker's velocity at each horizon.
struct Estimate {
  Vec3 position_m{};
  Vec3 sigma_m{};
  std::vector<Vec3> predictions_m;
};

class Scene {
 public:
  explicit Scene(const SceneParams& params);

  void apply(const Detection& d);
  void apply(const Track& t);
  void apply(const Command& c);
  void apply(const Estop& e);
  void apply(const Truth& t);
  void apply(const Health& h);

  /// The last register_size positions the tracker accepted (oldest first).
  const std::deque<Vec3>& register_positions() const { return register_; }
  /// The estimate when the latest track holds a valid position.
  std::optional<Estimate> estimate() const;
  const std::optional<Track>& track() const { return track_; }
  const std::optional<Truth>& truth() const { return truth_; }
  const std::deque<Detection>& detections() const { return detections_; }
  const std::deque<Command>& commands() const { return commands_; }
  const std::optional<Estop>& estop() const { return estop_; }
  /// Detection of frame frame_seq if still kept.
  std::optional<Detection> detection_for(uint64_t frame_seq) const;
  /// Changes since construction; lets a sender skip unchanged scenes.
  uint64_t version() const { return version_; }

  /// Everything as one JSON object ("type": "scene"); now_ns decides which nodes are stale.
  nlohmann::json to_json(int64_t now_ns) const;

 private:
  SceneParams params_;
  uint64_t version_ = 0;
  std::deque<Detection> detections_;
  std::optional<Track> track_;
  std::deque<Vec3> register_;
  std::deque<Command> commands_;
  std::optional<Estop> estop_;
  std::optional<Truth> truth_;
  std::map<std::string, Health> health_;  // by component@host:pid
};

/// Plain JSON of each value (used by Scene::to_json and by tests).
nlohmann::json to_json(const Detection& d);
nlohmann::json to_json(const Track& t);

}  // namespace stereoball::viewer
