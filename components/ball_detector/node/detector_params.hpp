#pragma once
// Parameters of the stereo ball detection pipeline (rectify, Pixel-to-Pixel on both eyes,
// epipolar pairing, triangulation, size check).

#include <cstdint>
#include <optional>
#include <string>

#include "ball_detector/core/appearance_model.hpp"
#include "ball_detector/core/p2p_detector.hpp"

namespace stereoball::ball_detector {

/// Which single-channel image the detector sees.
enum class DetectorInput {
  kGrey,  ///< luminance (BGR -> grey); a coloured ball can vanish on a floor of equal brightness
  kSaturation,  ///< max(B,G,R) - min(B,G,R): coloured ball against grey/brown surroundings
  kValue,       ///< max(B,G,R): a coloured ball with white patches looks uniform
  kRed,         ///< red channel: an orange/red ball with white patches looks uniform
  kGreen,       ///< green channel
  kBlue,        ///< blue channel
};

/// Name used in the config file ("grey", "saturation", "value", "red", "green", "blue").
const char* to_string(DetectorInput input);

/// The input named by text, or nullopt.
std::optional<DetectorInput> parse_detector_input(const std::string& text);

/// The Pixel-to-Pixel settings the pipeline starts from (config/ball_detector.yaml mirrors
/// them): the core's defaults with a Canny floor that keeps shading ramps on the ball out.
PixelToPixelParams pipeline_p2p_defaults();

/// Everything the stereo pipeline needs besides the calibration.
struct BallDetectorParams {
  DetectorInput input = DetectorInput::kRed;  ///< image the detector runs on (mono8: grey)
  double ball_diameter_m = 0.22;              ///< true ball diameter, metres, (0, 5]
  double epipolar_tolerance_px = 2.0;     ///< largest |y_left - y_right| of a pair, px, [0, 100]
  double size_max_relative_error = 0.15;  ///< accepted |r - r_expected| / r_expected, (0, 10]
  /// Search the right eye only in the boxes where a size-consistent partner of a left circle
  /// can lie (rows within the epipolar tolerance, disparity from the ball size at the size
  /// tolerance); false = the whole right image.
  bool right_eye_partner_boxes = true;
  /// Addition: when no right circle pairs with a left one, look for the right outline the left
  /// circle's ball makes along its epipolar line (scored against the right edges, p2p.min_score
  /// to pass). For a ball cut by the border each eye sees a different part and fits a different
  /// circle, rows apart.
  bool predicted_partner = true;
  /// The border rule for a predicted outline: it counts when this much of it is in the right
  /// image, [0, 1]. The outline is fixed but for its disparity, so less than a free circle needs.
  double predicted_partner_min_inside_fraction = 0.2;
  int max_candidates_per_eye = 5;  ///< circles kept per eye (P2P max_circles), [1, 50]
  /// Pairs within this distance of where the following track expects the ball are preferred
  /// to better-scoring pairs elsewhere, metres, [0, 10] (0 = off).
  double track_prior_gate_m = 0.3;
  /// With a prior, search first only the left box where the expected ball can appear (and its
  /// right partner boxes); the whole frame only if no pair turns up within the gate there.
  bool prior_window = true;
  /// A track older than this (its capture stamp vs the frame's) is not used as a prior, ns.
  std::int64_t track_prior_max_age_ns = 500'000'000;
  /// Where the prior says the ball is, a circle cut by the image border counts when this much
  /// of it is inside (elsewhere p2p.min_inside_fraction applies), [0, 1].
  double prior_min_inside_fraction = 0.3;
  /// Floor check (addition): a ball rests on the floor, its centre one radius above it. The
  /// left camera's optical centre is floor_camera_height_m above the floor and pitched down by
  /// floor_camera_pitch_rad (rotation about its x axis, before rectification); pairs whose
  /// centre is more than floor_tolerance_m from the resting height are rejected (0 = off: a
  /// bouncing ball). A pitch error of 1 degree moves a ball 5 m away by 9 cm.
  double floor_camera_height_m = 0.30;   ///< metres, [0, 10]
  double floor_camera_pitch_rad = 0.20;  ///< radians, [-1.57, 1.57]
  double floor_tolerance_m = 0.10;       ///< metres, [0, 10] (0 = no floor check)
  /// Measure circles against the ellipse a sphere images as where they are (each eye's
  /// rectified camera, from stereo/calibration); false = as circles (the paper).
  bool perspective_outline = true;
  PixelToPixelParams p2p = pipeline_p2p_defaults();  ///< detector on each rectified eye
  /// Addition: the followed ball's colour, learnt while the tracker follows it, ranks the left
  /// candidates and rejects round things of another colour; forgotten after a long loss.
  AppearanceParams appearance;

  /// Names the first bad field and its allowed range, or nullopt.
  std::optional<std::string> validate() const;

  /// The detector parameters with max_circles taken from max_candidates_per_eye.
  PixelToPixelParams detector_params() const;
};

}  // namespace stereoball::ball_detector
