#pragma once
// Pairs circle candidates of the two rectified eyes: epipolar row check, triangulation,
// size consistency with the known ball diameter, then the best pair. Pure.

#include <opencv2/core.hpp>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "ball_detector/core/circle.hpp"
#include "ball_detector/core/p2p_detector.hpp"
#include "stereo/core/epipolar.hpp"
#include "stereo/core/triangulation.hpp"

namespace stereoball::ball_detector {

/// Outcome of pairing, mirroring the non-error detection statuses.
enum class PairingStatus { kFound, kNoCandidate, kEpipolarMismatch, kSizeInconsistent, kOffFloor };

/// Where a ball can be: resting on the floor, its centre one radius above it (addition: a
/// ball-sized round thing on a wall or a box is not the ball).
struct FloorModel {
  cv::Vec3d up{0.0, -1.0, 0.0};  ///< unit up direction in the left rectified camera frame
  double camera_height_m = 0.3;  ///< left camera's optical centre above the floor, metres
  double tolerance_m = 0.1;      ///< largest |centre height - ball radius| accepted, metres
  /// Height above the floor of a point in the left rectified camera frame, metres.
  double height_m(const cv::Vec3d& p) const { return camera_height_m + up.dot(p); }
};

/// One left/right candidate pair that passed the row check and triangulated.
struct StereoPair {
  std::size_t left_index = 0;    ///< index into the left candidates
  std::size_t right_index = 0;   ///< index into the right candidates
  Circle left;                   ///< left circle, rectified pixels
  Circle right;                  ///< right circle, rectified pixels
  double row_residual_px = 0.0;  ///< |y_left - y_right|, rectified pixels
  cv::Vec3d position_m;          ///< centre in the left rectified camera frame, metres
  double depth_from_size_m =
      0.0;  ///< depth implied by the radii and diameter, metres (0 = unknown)
  double expected_radius_px = 0.0;  ///< radius the ball should have at position_m's depth, pixels
  double size_error = 0.0;          ///< (mean radius - expected) / expected
  bool size_consistent = false;     ///< |size_error| within tolerance
  double height_error_m = 0.0;      ///< centre height above the floor - ball radius, metres
  bool on_floor = true;             ///< |height_error_m| within the floor tolerance (or no floor)
  double score = 0.0;               ///< mean of both circles' scores, [0, 1]
  /// Addition (unsynchronised eyes, PairingContext::motion_radii): the disparity disagreed with
  /// the ball's size by more than the size tolerance, by no more than the ball can have moved
  /// between the exposures (position_m is still the triangulated one).
  bool moved = false;
};

/// Result of pairing one frame's candidates.
struct PairingResult {
  PairingStatus status = PairingStatus::kNoCandidate;
  std::string reason;              ///< human-readable detail of status
  std::optional<StereoPair> best;  ///< the chosen pair (kFound), or the closest rejected one
  int row_matches = 0;             ///< pairs that passed the row check and triangulated
  int size_matches = 0;            ///< of those, pairs whose size fits the ball
};

/// The geometry pairing needs; all references must outlive the call.
struct PairingContext {
  const stereo::EpipolarCheck& epipolar;
  const stereo::Triangulator& triangulator;
  const stereo::SizeCheckParams& size;
  std::optional<FloorModel> floor;  ///< no floor check without one
  /// Addition (unsynchronised eyes): how far the ball can move between the two eyes' exposures,
  /// in radii of its outline (speed x skew / ball radius: the same at every depth, as the
  /// outline and the motion both shrink with distance). A pair's rows may then differ by the
  /// epipolar tolerance plus this times its mean radius, and its disparity may miss the one its
  /// size implies by as much more. 0 = the eyes are synchronised (the paper's row rule).
  double motion_radii = 0.0;
  /// Addition: a found pair is withdrawn when a pair of clearly stronger outlines (mean score
  /// at least this much higher, radii agreeing between the eyes, at least as large) lies on
  /// allowed rows but fails the size check: a small round thing in clutter must not be
  /// reported while the frame's strongest sphere-like outline pair says something else (the
  /// ball moved more than allowed between unsynchronised exposures). 0 = off (the paper); off
  /// as well when motion_radii is 0 (synchronised eyes).
  double dominance_margin = 0.0;
};

/// Addition: whether the best size-consistent pair without motion (its disparity fits its size
/// within the size tolerance) is to be reported instead of best, which needed the motion
/// allowance: when it is larger and scores at most dominance_margin less. A small circle in
/// clutter passes the size check only thanks to that allowance more often than the ball does.
bool prefer_unmoved(const PairingContext& ctx, const StereoPair& unmoved, const StereoPair& best);

/// Addition: the size-inconsistent pair among candidates that dominates found (see
/// PairingContext::dominance_margin), nullopt if none does or the margin is 0.
std::optional<StereoPair> dominating_pair(const PairingContext& ctx, const StereoPair& found,
                                          const std::vector<StereoPair>& size_rejected);

/// Largest row difference a pair of circles with mean radius radius_px may have: the epipolar
/// tolerance plus the ball's image motion between the exposures (motion_radii), pixels.
double row_allowance_px(const PairingContext& ctx, double radius_px);

/// Addition: one eye's outline of a pair to fit again with the radius the other eye's implies.
/// Both eyes see one sphere, so their outline radii differ only as their views do (the sphere
/// outlines at position_m). A larger difference means texture just inside one rim, a panel or
/// stripe boundary, pulled that eye's fit inwards on one side: its radius is the smaller, and
/// its centre, and with it the disparity, moved by up to the difference.
struct RadiusBalance {
  bool right_eye = false;  ///< the eye whose outline is refitted (false: the left)
  double radius_px = 0.0;  ///< the radius to hold there, pixels
};

/// The refit a pair needs: when its radii, the view difference allowed for, differ by more than
/// max(min_px, fraction x radius), the eye with the smaller; nullopt otherwise.
std::optional<RadiusBalance> radius_balance(const stereo::Triangulator& tri, const Circle& left,
                                            const Circle& right, const cv::Vec3d& position_m,
                                            double ball_radius_m, double min_px, double fraction);

/// The rectified right-image box where a size-consistent partner of left can lie: the ball
/// size gives the depth (within the size tolerance), the depth the disparity, the epipolar
/// tolerance the rows; padded by margin_px (the detector's window) and clipped to image. Empty
/// if no partner can be in the image.
cv::Rect partner_search_box(const PairingContext& ctx, const Circle& left, cv::Size image,
                            int margin_px);

/// Where the tracker expects the ball now (left rectified frame, metres): among the
/// size-consistent pairs, those within gate_m of it are preferred to better-scoring ones
/// elsewhere (a look-alike that outscores the ball in some frames then cannot take over).
struct PositionPrior {
  cv::Vec3d position_m;
  double gate_m = 0.3;
  cv::Vec3d velocity_mps{0.0, 0.0, 0.0};  ///< the track's, same frame, m/s
};

/// What the detector needs of the tracker's latest ball/track.
struct TrackedBall {
  bool following = false;             ///< state FOLLOWING
  bool position_valid = false;        ///< position/velocity hold an accepted estimate
  cv::Vec3d position_m;               ///< left rectified frame, metres
  cv::Vec3d velocity_mps;             ///< same frame, m/s
  std::int64_t capture_stamp_ns = 0;  ///< capture stamp of the frame behind the track
};

/// The prior for a frame captured at frame_stamp_ns: the track's position moved on by its
/// velocity; nullopt unless following with a valid position no older than max_age_ns (and
/// not from the future by more than that), or gate_m is 0.
std::optional<PositionPrior> prior_from_track(const TrackedBall& track, std::int64_t frame_stamp_ns,
                                              double gate_m, std::int64_t max_age_ns);

/// The pixels within reach_px of centre (a square, rounded outwards), clipped to image.
cv::Rect box_around(const cv::Point2d& centre, double reach_px, cv::Size image);

/// The box an outline refined from seed can reach: the polish's first band beyond the seed
/// (prediction error), the radius at the size tolerance (an off-axis ball's ellipse), and a
/// pixel of rounding; clipped to image.
cv::Rect seed_box(const Circle& seed, double tolerance, cv::Size image);

/// c moved by the vector by (between a box's and the image's coordinates).
Circle shifted(Circle c, cv::Point by);

/// The left rectified-image box where the ball expected at prior can appear: its disc (a third
/// of the gate nearer, at the size tolerance) plus a third of the gate sideways, padded by
/// margin_px and clipped; empty if the prior is not in front of the camera.
cv::Rect prior_search_box(const PairingContext& ctx, const PositionPrior& prior, cv::Size image,
                          int margin_px);

/// The outlines of the ball exactly where prior expects it, as circles (outline centre, mean
/// radius; score 0) in the left and right rectified images.
struct ExpectedOutlines {
  Circle left;
  Circle right;
};
/// nullopt if the prior is not in front of both cameras by more than the ball's radius.
std::optional<ExpectedOutlines> prior_outlines(const PairingContext& ctx,
                                               const PositionPrior& prior);

/// Radii (mean outline radius, pixels) the left eye can see the ball expected at prior with:
/// from a third of the gate farther to a third nearer, within the size tolerance, the
/// ellipse's semi-axes included (votes reach its centre from either).
RadiusRange prior_radius_range(const PairingContext& ctx, const PositionPrior& prior);

/// How far outside the image (pixels, rounded up) the left outline centre of the ball expected
/// at prior can lie, with the prior's slack; 0 when it is inside. Capped at the largest radius
/// the ball can have there: a centre farther out leaves nothing of the ball in view.
int prior_centre_margin_px(const PairingContext& ctx, const PositionPrior& prior, cv::Size image);

/// The same for the right-eye partners of left: centres along each one's row, over the
/// disparities its size allows; 0 when all lie inside the image.
int partner_centre_margin_px(const PairingContext& ctx, const std::vector<Circle>& left,
                             cv::Size image);

/// Addition: the right-eye outlines of the ball behind the left circle, over the disparities the
/// size check allows, step_px of disparity apart (nearest ball first): the left outline gives
/// the ball's line of sight (a sphere of known size), each depth on it one right outline.
/// Every one lies on the left circle's rows, as the ball's do. Empty if the left circle is no
/// sphere's outline.
std::vector<Circle> partner_outlines(const PairingContext& ctx, const Circle& left, double step_px);

/// Scores a right-eye outline (right rectified px) against that eye's edges, [0, 1].
using OutlineScorer = std::function<double(const Circle&)>;

/// Addition: the right-eye partner of left found along its epipolar line when no detected
/// right circle pairs with it (a ball cut by the border, whose part in view each eye fits
/// differently): the best-scoring partner_outlines at 1 px of disparity, then at 0.25 px
/// around it, each time the middle of the best-scoring run (coverage scores are flat over a
/// pixel or more); nullopt if none scores min_score, or if with a floor model no ball in the
/// left circle's cone could rest on the floor (the scorer is then not called). The result
/// carries its score.
std::optional<Circle> predicted_partner(const PairingContext& ctx, const Circle& left,
                                        const OutlineScorer& score, double min_score);

/// Radii a right-eye partner of any of left can have: each within the size tolerance of its
/// left circle (the eyes see nearly the same outline), plus 2 px.
RadiusRange partner_radius_range(const PairingContext& ctx, const std::vector<Circle>& left);

/// True if a should be preferred to b: higher score, then smaller row residual.
bool better_pair(const StereoPair& a, const StereoPair& b);

/// Evaluates one left/right pair; nullopt if it fails the row check or does not triangulate
/// in front of the rig.
std::optional<StereoPair> evaluate_pair(const PairingContext& ctx, const Circle& left,
                                        const Circle& right);

/// Every candidate combination -> the best size-consistent pair on the floor (within the
/// prior's gate when one is given and any pair is, else overall), or the reason there is none.
PairingResult pair_candidates(const PairingContext& ctx, const std::vector<Circle>& left,
                              const std::vector<Circle>& right,
                              const std::optional<PositionPrior>& prior = std::nullopt);

}  // namespace stereoball::ball_detector
