#pragma once
// A scenario: the room, clutter, ball, scripted events and lighting of one simulated run.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/util/result.hpp"
#include "simulator/core/board_scene.hpp"
#include "simulator/core/vec3.hpp"

namespace stereoball::simulator {

/// An sRGB-ish colour, components 0..255.
struct Rgb {
  double r = 0.0, g = 0.0, b = 0.0;
};

/// Floor texture (RoomSpec::plain overrides it with floor_a only).
enum class FloorPattern {
  kTiles,   ///< square tiles of tile_m, floor_a / floor_b checkered, grout lines
  kPlanks,  ///< wooden planks tile_m / 4 wide along x, staggered ends, per-plank shade
  kCarpet   ///< fine noise around floor_a (1 cm cells), floor_b mixed in
};

/// Axis-aligned room: floor z = 0, ceiling z = height_m, four walls.
struct RoomSpec {
  double x_min_m = -2.0, x_max_m = 6.0;  ///< wall positions along x, metres
  double y_min_m = -3.0, y_max_m = 3.0;  ///< wall positions along y, metres
  double height_m = 2.5;                 ///< ceiling height, metres
  double tile_m = 0.5;                   ///< floor tile size, metres
  double grout_m = 0.015;                ///< floor grout line width, metres
  Rgb floor_a{150, 120, 90}, floor_b{135, 105, 80}, grout{70, 60, 55};  ///< floor colours
  Rgb wall{190, 195, 200};                                              ///< wall colour
  Rgb baseboard{90, 80, 75};   ///< 10 cm strip at the bottom of every wall
  Rgb ceiling{215, 215, 215};  ///< ceiling colour
  bool plain = false;          ///< untextured floor (floor_a only) and no baseboard
  FloorPattern floor_pattern = FloorPattern::kTiles;
};

/// A box standing on the floor, axis-aligned.
struct BoxSpec {
  double x_m = 0.0, y_m = 0.0;                            ///< centre of the footprint, metres
  double size_x_m = 0.4, size_y_m = 0.4, size_z_m = 0.4;  ///< extent, metres
  double z_m = 0.0;                                       ///< bottom height, metres
  Rgb color{120, 90, 60};
};

/// A door frame (two jambs and a lintel) with a closed door leaf, against a wall.
struct DoorFrameSpec {
  double x_m = 0.0, y_m = 0.0;  ///< centre of the opening at floor level, metres
  bool along_x = false;         ///< opening spans along x (wall at constant y) or along y
  double width_m = 0.9;         ///< opening width, metres
  double height_m = 2.0;        ///< opening height, metres
  double jamb_m = 0.08;         ///< jamb/lintel thickness in the wall plane, metres
  double depth_m = 0.12;        ///< how far the frame sticks out of the wall, metres
  Rgb color{240, 240, 235};     ///< frame colour
  Rgb door_color{130, 85, 50};  ///< door leaf colour
};

/// A round flat object (plate, clock, sign): a disc with a rim.
struct PlateSpec {
  Vec3d center_m{0.0, 0.0, 1.0};  ///< disc centre, world metres
  Vec3d normal{-1.0, 0.0, 0.0};   ///< facing direction (normalised on use)
  double radius_m = 0.12;
  double rim_m = 0.015;  ///< width of the rim ring, metres
  Rgb color{230, 120, 40};
  Rgb rim_color{250, 250, 250};
};

/// A static one-colour sphere (a distractor: another ball, a round thing on a box).
struct SphereSpec {
  Vec3d center_m{2.0, 0.5, 0.1};  ///< world metres (on the floor: z = radius)
  double radius_m = 0.1;
  Rgb color{40, 90, 200};
};

/// How the ball's two colours are laid out on it.
enum class BallPattern {
  kFootball,  ///< color_b patches around the 12 icosahedron vertices
  kSolid,     ///< color_a only
  kPanels,    ///< six longitudinal panels, alternating color_a / color_b (a beach ball)
  kStripes    ///< latitude bands, alternating color_a / color_b
};

/// The ball at scenario start.
struct BallSpec {
  double x_m = 1.5, y_m = 0.0;        ///< on the floor, metres
  double vx_mps = 0.0, vy_mps = 0.0;  ///< initial velocity, m/s
  double radius_m = 0.11;
  Rgb color_a{230, 110, 20};   ///< main colour
  Rgb color_b{245, 245, 245};  ///< patch colour
  BallPattern pattern = BallPattern::kFootball;
};

/// Sets the ball velocity at a time (a kick).
struct KickSpec {
  double t_s = 0.0;
  double vx_mps = 0.0, vy_mps = 0.0;
};

/// Lighting keyframe; values are linearly interpolated between keys.
struct LightKey {
  double t_s = 0.0;
  double ambient = 0.45;  ///< ambient light level, 0..2
  double sun = 0.65;      ///< directional light level, 0..2
  double exposure = 1.0;  ///< camera exposure multiplier, 0.05..5
};

/// A velocity command held from t_s on (the standalone tool's built-in driver).
struct ScriptedCommand {
  double t_s = 0.0;
  double linear_mps = 0.0;
  double angular_radps = 0.0;
};

/// Everything a run needs besides the hardware parameters.
struct Scenario {
  std::string name = "unnamed";
  uint64_t seed = 1;
  double duration_s = 10.0;
  RoomSpec room;
  double robot_x_m = 0.0, robot_y_m = 0.0, robot_yaw_rad = 0.0;  ///< start pose
  /// A slower base than the simulator params' robot.max_angular_radps (never faster), rad/s.
  std::optional<double> robot_max_angular_radps;
  std::optional<BallSpec> ball;
  std::vector<BoxSpec> boxes;
  std::vector<DoorFrameSpec> door_frames;
  std::vector<PlateSpec> plates;
  std::vector<SphereSpec> spheres;
  std::vector<KickSpec> kicks;
  double sun_azimuth_rad = 2.4;    ///< direction the light comes from, CCW from +x (behind-left)
  double sun_elevation_rad = 1.0;  ///< above the horizon, radians
  std::vector<LightKey> lighting;  ///< sorted by t_s; empty = LightKey defaults
  std::vector<ScriptedCommand> commands;  ///< sorted by t_s
  /// A calibration scene: the simulator renders a chessboard carried in front of the rig on a
  /// plain background instead of the room (see core/board_scene.hpp).
  std::optional<CalibrationScene> calibration;

  /// Success, or the first invalid field with its allowed range.
  Status validate() const;
};

/// An axis-aligned solid box in the world (boxes and door-frame parts), metres.
struct SolidBox {
  Vec3d lo, hi;
  Rgb color;
};

/// Every solid box of the scenario: its boxes, then 4 per door frame (jambs, lintel, leaf).
std::vector<SolidBox> solid_boxes(const Scenario& s);

/// Lighting at time t_s (interpolated keyframes).
LightKey lighting_at(const Scenario& s, double t_s);

/// Scripted command in force at t_s, or nullopt before the first one.
std::optional<ScriptedCommand> scripted_command_at(const Scenario& s, double t_s);

}  // namespace stereoball::simulator
