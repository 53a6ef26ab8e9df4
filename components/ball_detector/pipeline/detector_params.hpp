#pragma once
// Parameters of the stereo ball detection pipeline (rectify, Pixel-to-Pixel on both eyes,
// epipolar pairing, triangulation, size check).

#include <opencv2/core.hpp>

#include <cstdint>
#include <optional>
#include <string>

#include "ball_detector/core/appearance_model.hpp"
#include "ball_detector/core/coarse_to_fine.hpp"
#include "ball_detector/core/colour_seeds.hpp"
#include "ball_detector/core/p2p_detector.hpp"
#include "ball_detector/pipeline/interior_depth.hpp"
#include "ball_detector/pipeline/outline_refit.hpp"
#include "common/params/field_table.hpp"
#include "common/util/result.hpp"

namespace stereoball::ball_detector {

/// Which single-channel image the detector sees.
enum class DetectorInput {
  kGrey,  ///< luminance (BGR -> grey); a coloured ball can vanish on a floor of equal brightness
  kSaturation,  ///< max(B,G,R) - min(B,G,R): coloured ball against grey/brown surroundings
  kValue,       ///< max(B,G,R): a coloured ball with white patches looks uniform
  kRed,         ///< red channel: an orange/red ball with white patches looks uniform
  kGreen,       ///< green channel
  kBlue,        ///< blue channel
  /// All three channels: edges from the channel that changes most at each pixel (core
  /// EdgeParams::colour), so no channel has to be chosen for the ball's colour.
  kColour,
};

/// Name used in the config file ("grey", "saturation", "value", "red", "green", "blue",
/// "colour").
const char* to_string(DetectorInput input);

/// The input named by text, or nullopt.
std::optional<DetectorInput> parse_detector_input(const std::string& text);

/// Everything the stereo pipeline needs besides the calibration. Each configured field's key,
/// default, range, unit and meaning: detector_fields(); the comments here say why.
struct BallDetectorParams {
  BallDetectorParams();  ///< every field at its default from detector_fields()

  DetectorInput input;  ///< image the detector runs on (mono8 frames: grey)
  double ball_diameter_m;
  double epipolar_tolerance_px;
  /// Addition (unsynchronised eyes): the fastest the ball moves, m/s. Between the two eyes'
  /// exposures (epipolar_skew_ns apart) it moves speed x skew, which in its own image is that
  /// over its radius times its outline radius at any depth: the rows of a pair may differ by
  /// that much more than epipolar_tolerance_px, and its disparity may miss the size's by as
  /// much (the depth is then the radii's). 0 = off (the paper's rows). With a following track
  /// the track's speed (plus kTrackSpeedSlackMps) is used when lower.
  double epipolar_ball_speed_mps;
  /// Time between the two eyes' exposures, ns: -1 = from each frame's two capture stamps;
  /// >= 0 = this (stills, a file source or a driver whose stamps do not tell; 0 = synchronised).
  std::int64_t epipolar_skew_ns;
  double size_max_relative_error;
  /// Search the right eye only in the boxes where a size-consistent partner of a left circle
  /// can lie (rows within the epipolar tolerance, disparity from the ball size at the size
  /// tolerance); false = the whole right image.
  bool right_eye_partner_boxes;
  /// Addition: a found pair whose two outline radii disagree beyond what the two views explain
  /// has the eye with the smaller refitted, centre only, at the radius the other implies
  /// (radius_balance in pairing.hpp): the disparity of a small ball far away depends on it.
  bool balance_radii;
  /// Addition: when no right circle pairs with a left one, look for the right outline the left
  /// circle's ball makes along its epipolar line (scored against the right edges, p2p.min_score
  /// to pass). For a ball cut by the border each eye sees a different part and fits a different
  /// circle, rows apart.
  bool predicted_partner;
  /// The outline is fixed but for its disparity, so it needs less inside than a free circle.
  double predicted_partner_min_inside_fraction;
  int max_candidates_per_eye;  ///< P2P max_circles
  /// Pairs near where the following track expects the ball are preferred to better-scoring
  /// pairs elsewhere (0 = off).
  double track_prior_gate_m;
  /// With a prior, search first only the left box where the expected ball can appear (and its
  /// right partner boxes); the whole frame only if no pair turns up within the gate there.
  bool prior_window;
  /// With prior_window, first refine the outlines the prior predicts in each eye (no voting);
  /// the box is searched by voting only when that pairs nothing within the gate.
  bool prior_seeded;
  std::int64_t track_prior_max_age_ns;  ///< against the frame's capture stamp
  /// Where the prior says the ball is, a circle cut by the image border counts with this much
  /// of it inside (elsewhere p2p.min_inside_fraction applies).
  double prior_min_inside_fraction;
  /// Floor check (addition): a ball rests on the floor, its centre one radius above it. The
  /// left camera's optical centre is floor_camera_height_m above the floor and pitched down by
  /// floor_camera_pitch_rad (rotation about its x axis, before rectification); pairs whose
  /// centre is more than floor_tolerance_m from the resting height are rejected (0 = off: a
  /// bouncing ball). A pitch error of 1 degree moves a ball 5 m away by 9 cm.
  double floor_camera_height_m;
  double floor_camera_pitch_rad;
  double floor_tolerance_m;
  /// Measure circles against the ellipse a sphere images as where they are (each eye's
  /// rectified camera, from stereo/calibration); false = as circles (the paper).
  bool perspective_outline;
  /// Detector on each rectified eye: the keys under p2p: set some fields, the rest keep the
  /// core's defaults.
  PixelToPixelParams p2p;
  /// Addition: the image width p2p's window sizes (k_values) and pixel lengths (radii,
  /// separation, clutter-ring start) are chosen for. A wider camera sees the same scene in more
  /// pixels: its k and lengths are scaled by width / this, so each window covers the same part of
  /// the scene and an outline's arc bends as much across it (a k chosen for 640 px sees a ball's
  /// arc at 2304 px as a straight segment). 0 = as configured at every width.
  int p2p_reference_width_px;
  /// Addition: frames wider than this are shrunk (area interpolation, as camera_server's
  /// publish_width_px) by the smallest whole factor that brings them to at most this width, the
  /// calibration with them, and searched there; the detection is mapped back to the frame's own
  /// rectified pixels. 0 = every frame at its own size.
  int working_width_px;
  /// Addition: the followed ball's colour, learnt while the tracker follows it, ranks the left
  /// candidates and rejects round things of another colour; forgotten after a long loss.
  AppearanceParams appearance;
  /// Addition: in a whole-frame search, regions of outstanding colour seed left candidates the
  /// votes missed (a two-tone ball whose light half matches the floor); refined and scored on
  /// the edges as every candidate is (colour_seeds.hpp).
  ColourSeedParams colour_seeds;
  /// Addition: a found pair whose textured inside matches between the eyes at another depth
  /// than its outline is a round pattern on a surface, not a ball (interior_depth.hpp).
  InteriorDepthParams interior_depth;
  /// Addition: a found pair's outlines fitted again, in both eyes, to the edge arcs that agree
  /// (fingers, seams), and the pair withdrawn when the refits do not pair (outline_refit.hpp).
  OutlineRefitParams outline_refit;
  /// Addition (speed): whole-frame and radius-band searches of a wide frame vote on the left eye
  /// reduced to about coarse_to_fine.target_width_px and refine each circle found there on the
  /// full-resolution edges (coarse_to_fine.hpp); target 0 = every search at full width.
  CoarseToFineParams coarse_to_fine;
  /// Addition (speed): a pair the reduced eye's circles give answers the frame only when its
  /// score reaches this; a weaker one is left to the full-width search, [0, 1].
  double coarse_min_pair_score;
  /// Addition (speed, off: a kicked ball of the randomised sets not tuned on was lost more
  /// often): frames not wider than coarse_to_fine.target_width_px (640x480) search the whole
  /// range's radii the halved eye resolves on its full-width edges halved, the rest only in
  /// the full-width radius bands, and no full-width whole-range search (README: by radius).
  bool coarse_by_radius;
  /// Addition: PairingContext::dominance_margin (0 = off).
  double dominance_margin;
  /// Largest image a calibration (and so every frame) may have: a larger stereo/calibration is
  /// refused before its rectification tables are allocated.
  int max_image_width_px;
  int max_image_height_px;

  /// max_image_width_px x max_image_height_px.
  cv::Size max_image_size() const { return {max_image_width_px, max_image_height_px}; }

  /// Success, or the first field out of its range or rule broken, naming the key.
  Status validate() const;

  /// The detector parameters with max_circles taken from max_candidates_per_eye.
  PixelToPixelParams detector_params() const;
};

/// p2p for images image_width_px wide (BallDetectorParams::p2p_reference_width_px): k_values
/// (rounded, within [1, 31]), radii, separation and the clutter rings' start scaled by
/// image_width_px / reference_width_px when that exceeds 1 and changes a rounded k; p2p itself
/// otherwise.
PixelToPixelParams scaled_to_width(const PixelToPixelParams& p2p, int reference_width_px,
                                   int image_width_px);

/// One row per key of config/ball_detector.yaml: the defaults, validate(), the loader, the
/// README table and `ball_detector --help-params` come from it.
const params::FieldTable<BallDetectorParams>& detector_fields();

}  // namespace stereoball::ball_detector
