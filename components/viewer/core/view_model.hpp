#pragma once
// What the viewer shows, as plain values (no DDS, no generated IDL types): the node converts
// each incoming message into one of these. Positions are in the left rectified camera frame
// (x right, y down, z forward, metres) unless a name says world.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace stereoball::viewer {

using Vec3 = std::array<double, 3>;

/// A circle in one rectified eye (pixels); score 0 when absent.
struct Circle {
  double x_px = 0;
  double y_px = 0;
  double radius_px = 0;
  double score = 0;
};

/// One detector result (ball/detection).
struct Detection {
  uint64_t frame_seq = 0;
  int64_t capture_stamp_ns = 0;
  bool found = false;
  std::string status;  ///< e.g. "found", "epipolar_mismatch"
  std::string reason;  ///< the detector's detail text (why a candidate was refused)
  Circle left;
  Circle right;
  double row_residual_px = 0;
  Vec3 position_m{};
  uint32_t candidates_left = 0;
  uint32_t candidates_right = 0;
  double processing_ms = 0;
  double latency_ms = 0;  ///< capture to the detector's publication
};

/// One tracker state (ball/track).
struct Track {
  uint64_t frame_seq = 0;
  int64_t capture_stamp_ns = 0;
  std::string state;    ///< "idle", "following", "searching"
  std::string verdict;  ///< e.g. "block_match_accepted"
  std::string reason;
  bool accepted = false;  ///< the verdict accepted this frame's position
  bool position_valid = false;
  Vec3 position_m{};
  Vec3 velocity_mps{};
  double bearing_rad = 0;  ///< positive = ball to the right
  double distance_m = 0;
  std::string last_seen_side;  ///< "left", "right", "unknown"
  double ssd = -1;
  double latency_ms = 0;  ///< capture to the tracker's publication
};

/// A velocity command (cmd/velocity).
struct Command {
  int64_t stamp_ns = 0;
  double linear_mps = 0;
  double angular_radps = 0;  ///< positive = turn left
};

/// The e-stop state (cmd/estop).
struct Estop {
  int64_t stamp_ns = 0;
  bool engaged = false;
  std::string reason;
};

/// Simulator ground truth (sim/ground_truth).
struct Truth {
  uint64_t frame_seq = 0;
  int64_t stamp_ns = 0;
  bool ball_present = false;
  double ball_radius_m = 0;
  Vec3 ball_world_m{};   ///< world frame: x, y on the floor, z up
  Vec3 ball_camera_m{};  ///< left rectified camera frame
  double robot_x_m = 0;
  double robot_y_m = 0;
  double robot_yaw_rad = 0;
};

/// A node heartbeat (health/status).
struct Health {
  struct Rate {
    std::string topic;
    double rate_hz = 0;
    uint64_t count = 0;
    uint64_t dropped = 0;
  };
  std::string component;
  std::string host;
  int32_t pid = 0;
  int64_t stamp_ns = 0;
  bool healthy = false;
  std::string state;
  std::vector<Rate> rates;
  uint64_t errors = 0;
  std::string last_error;
};

}  // namespace stereoball::viewer
