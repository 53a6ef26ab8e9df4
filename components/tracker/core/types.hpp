#pragma once
// Value types the tracker core consumes and produces. They mirror
// idl/stereoball.idl (BallDetection, BallTrack) without depending on it.

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

#include "tracker/core/track_state.hpp"

namespace stereoball::tracker {

/// Half size k of the block matching window, pixels (paper: k = 10).
inline constexpr int kBlockHalfSizePx = 10;
/// Side of the block matching window, pixels (2k + 1 = 21).
inline constexpr int kBlockSidePx = 2 * kBlockHalfSizePx + 1;
/// Bytes of one RGB block: 21 x 21 x 3 = 1323.
inline constexpr std::size_t kPatchBytes = kBlockSidePx * kBlockSidePx * 3;

/// A 21x21 RGB block, row-major, interleaved R, G, B, 8 bits per channel.
using Patch = std::array<std::uint8_t, kPatchBytes>;

/// Why the current detection was accepted or rejected (IDL TrackVerdict).
enum class Verdict {
  kNoDetection,          ///< the detector found nothing this frame
  kStartupCollecting,    ///< fewer than five positions so far
  kStartupInconsistent,  ///< five positions but they or the sixth are not consistent
  kStartupAccepted,      ///< first accepted position; reference block stored
  kBlockMatchAccepted,   ///< SSD below threshold
  kStatisticsAccepted,   ///< block match failed but statistics accept (reacquisition)
  kRejected              ///< neither block matching nor statistics accept
};

/// One ball detection as the tracker sees it (one per stereo frame).
struct Detection {
  bool found = false;                                    ///< a stereo-consistent ball was detected
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();  ///< left rectified frame, metres
  double left_x_px = 0.0;            ///< centre column in the left rectified image, px
  std::uint32_t image_width_px = 0;  ///< image width, px (0 = unknown)
  bool patch_valid = false;          ///< patch_rgb holds the block around the left centre
  Patch patch_rgb{};                 ///< 21x21 RGB block around the left centre
};

/// Tracker output after one detection (IDL BallTrack without transport fields).
struct Track {
  TrackState state = TrackState::kIdle;
  Verdict verdict = Verdict::kNoDetection;
  std::string reason;           ///< human-readable cause of the verdict
  bool position_valid = false;  ///< position/velocity hold an accepted estimate
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();    ///< last accepted position, m
  Eigen::Vector3d velocity_mps = Eigen::Vector3d::Zero();  ///< estimated velocity, m/s
  double bearing_rad = 0.0;                 ///< atan2(x, z); positive = ball to the right
  double distance_m = 0.0;                  ///< horizontal distance sqrt(x^2 + z^2), m
  Side last_seen_side = Side::kUnknown;     ///< where the ball was last accepted
  double ssd = -1.0;                        ///< block matching SSD of this frame (-1 if none)
  std::int64_t last_accepted_stamp_ns = 0;  ///< stamp of the last accepted detection, ns
};

/// True for the verdicts that accept the detection.
bool is_accepted(Verdict v);

/// Lower-case name of a state, e.g. "following".
std::string_view to_string(TrackState s);
/// Lower-case name of a side, e.g. "left".
std::string_view to_string(Side s);
/// Lower-case name of a verdict, e.g. "block_match_accepted".
std::string_view to_string(Verdict v);

}  // namespace stereoball::tracker
