#pragma once
// Additions beyond the paper: sub-pixel centre and radius by least-squares circle fit on edge
// points, and a [0, 1] score (how much of the circumference is backed by edge points).

#include "ball_detector/core/circle.hpp"
#include "ball_detector/core/edge_map.hpp"
#include "stereo/core/sphere_outline.hpp"

#include <opencv2/core.hpp>

#include <optional>
#include <span>
#include <vector>

namespace stereoball::ball_detector {

/// Least-squares circle through points: algebraic (Kasa) start, then geometric Gauss-Newton.
/// nullopt for fewer than 3 points or a degenerate (collinear) set. Score is left at 0.
/// robust_floor_px > 0: the Gauss-Newton steps weight each point by Tukey's biweight of its
/// distance to the circle, with a cut at max(robust_floor_px, 4.7 x the residuals' robust
/// sigma), so a minority of points off the outline (texture arcs just inside a ball's rim) no
/// longer pulls the fit; 0 = plain least squares.
/// fixed_radius_px > 0: the radius is held at it and only the centre is fitted (the Kasa
/// centre, then Gauss-Newton on the centre).
std::optional<Circle> fit_circle(std::span<const cv::Point2d> points, double robust_floor_px = 0.0,
                                 double fixed_radius_px = 0.0);

/// Options of the annulus gathering and scoring.
struct RefineParams {
  double band_px = 0.5;  ///< edge points within this distance of the circle count, pixels
  /// Addition: the band grows to this fraction of the radius when that is wider. A sphere off
  /// the optical axis images as an ellipse (axes differ by ~r(1/cos(theta) - 1), 2 px for r = 54
  /// px at 15 deg), which a 0.5 px band around the best circle would mostly miss.
  double band_per_radius = 0.025;
  double min_radial_cos = 0.85;  ///< min |cos| between edge gradient and the radius, [0, 1]
  int iterations = 3;            ///< gather + fit rounds
  /// Half width of the first round's band, px; each later round halves it (down to the
  /// scoring band).
  double first_band_px = 2.5;
  /// Addition: the fit's robust cut floor, px (fit_circle's robust_floor_px; 0 = least squares).
  double robust_fit_floor_px = 0.0;
  /// Addition: when > 0, the score is the outline's coverage minus the smaller coverage of the
  /// circles this fraction of the radius (at least 2 px) larger and smaller, so that dense
  /// texture, which covers every circle through it, does not score as an outline. A ball's
  /// outline has the ball on one side and the floor on the other, and at least one of them is
  /// cleaner than texture around a chance circle: patterned ball on a plain floor, plain ball on
  /// carpet. 0 = off.
  double clutter_ring_per_radius = 0.0;
  /// Addition: the clutter rings apply only to circles at least this large, pixels, and weigh
  /// in gradually up to twice this radius (weight r / clutter_min_radius_px - 1; 0 = full
  /// weight at every radius). The scoring band grows with the radius (band_per_radius), and a
  /// wide band over texture collects edge points in most sectors by chance; a small circle's
  /// band is narrow, and a patterned ball on textured ground has texture on both sides.
  double clutter_min_radius_px = 0.0;
  /// Addition (speed): when > 0, a caller that drops circles scoring below this says so, and
  /// refinement stops early on a candidate that cannot reach it: after the first (widest)
  /// round, if the coverage of the points gathered is below it (the score is coverage in a
  /// narrower band, so it is about the most the candidate can reach), and the clutter rings
  /// are not measured when the coverage alone is below it. 0 = refine every candidate fully.
  double give_up_below = 0.0;
  /// Addition: the rough circle's radius is held and only the centre is refined. For an outline
  /// whose radius is known from elsewhere (the other eye's view of the same sphere): texture
  /// just inside a rim can no longer shrink the circle onto itself on one side.
  bool hold_radius = false;
  /// A circle cut by the image border scores 0 unless this fraction of it is inside, [0, 1].
  double min_inside_fraction = 0.5;
  /// Addition: the (rectified, undistorted) camera of the whole image, when known. A sphere off
  /// the optical axis images as an ellipse (sphere_outline); with the camera the refinement and
  /// the score measure edge points against that ellipse instead of a circle, and the circle
  /// returned has the ellipse's centre and the mean of its semi-axes as radius. Without it,
  /// circles are measured as circles.
  std::optional<stereo::PinholeCamera> camera;
};

/// The affine map that turns the outline a sphere images as around a centre into a circle
/// (its minor semi-axis): a compression by 1 / ratio along axis. ratio 1 = identity.
struct OutlineStretch {
  cv::Point2d axis{1.0, 0.0};  ///< unit major-axis direction
  double ratio = 1.0;          ///< semi-major / semi-minor, >= 1
  bool identity() const { return ratio == 1.0; }
  /// An offset from the centre, in stretched (round) coordinates.
  cv::Point2d to_round(const cv::Point2d& d) const;
  /// An offset in round coordinates, back in the image.
  cv::Point2d from_round(const cv::Point2d& d) const;
  /// A gradient (normal direction) in round coordinates.
  cv::Point2d gradient_to_round(const cv::Point2d& g) const;
};

/// The stretch for a sphere whose outline has centre and mean radius c in edges' image, from
/// params.camera (identity without one, or for an outline no sphere makes).
OutlineStretch outline_stretch(const EdgeMap& edges, const Circle& c, const RefineParams& params);

/// Edge points within band_px of circle c whose gradient is radial, each moved to its sub-pixel
/// position along the gradient (parabola through three gradient magnitudes).
void gather_circle_points(const EdgeMap& edges, const Circle& c, double band_px,
                          double min_radial_cos, std::vector<cv::Point2d>& out);

/// gather_circle_points in stretched coordinates: round is the circle the outline becomes
/// (centre, minor semi-axis); the edge points within band_px of it and with a normal gradient
/// there after stretch are returned, in round coordinates (centre + to_round(p - centre)).
void gather_outline_points(const EdgeMap& edges, const Circle& round, const OutlineStretch& stretch,
                           double band_px, double min_radial_cos, std::vector<cv::Point2d>& out);

/// Half-width of the band around circle c whose edge points support it, pixels.
double scoring_band_px(const Circle& c, const RefineParams& params);

/// Fraction in [0, 1] of angular sectors of circle c holding at least one of points.
double angular_coverage(const Circle& c, std::span<const cv::Point2d> points);

/// Addition: angular_coverage counting only the sectors whose arc lies inside frame (the whole
/// camera image, in the points' coordinates): a ball cut by the image border is judged on its
/// visible part. 0 when less than min_inside of the circle is inside. With a stretch, c and
/// points are in its round coordinates (gather_outline_points) and the frame test maps back.
double angular_coverage_in_frame(const Circle& c, std::span<const cv::Point2d> points,
                                 const cv::Rect2d& frame, double min_inside = 0.5,
                                 const OutlineStretch& stretch = {});

/// Radius around centre (cx, cy) best supported by edge points with a radial gradient: the
/// 2-px ring holding the most points per unit of circumference; nullopt if no ring has 8 points.
std::optional<double> estimate_radius(const EdgeMap& edges, double cx, double cy,
                                      double min_radius_px, double max_radius_px);

/// Refines a rough circle by repeated gather + fit, then scores it by angular coverage;
/// nullopt if the fit fails. The result's centre is sub-pixel.
std::optional<Circle> refine_circle(const EdgeMap& edges, const Circle& rough,
                                    const RefineParams& params);

/// Score only (no refinement): angular coverage of c's gathered edge points.
double score_circle(const EdgeMap& edges, const Circle& c, const RefineParams& params);

/// Addition: settings of robust_outline (the outline of a ball partly hidden by fingers or
/// crossed by seams, found from the arcs that agree).
struct OutlineSearchParams {
  /// Hypotheses may have a radius within this fraction of the rough one, either way.
  double radius_slack = 0.3;
  /// ... and a centre within this fraction of the rough radius of the rough centre.
  double centre_slack = 0.4;
  double band_px = 1.5;            ///< an edge point this close to a hypothesis supports it, px
  double band_per_radius = 0.025;  ///< ... or this fraction of its radius when wider
  double min_radial_cos = 0.9;     ///< and its gradient must be this radial, abs(cos), [0, 1]
  int hypotheses = 600;            ///< circles through three sampled edge points tried
  /// An edge point supports only if the colour this fraction of the radius inside it (at least
  /// 2 px) is nearer the ball's (the median inside the rough circle) than the colour as far
  /// outside by this much (Euclidean, 8-bit channels): an outline has the ball on one side
  /// only, a seam or a shading step on both. 0 = no side test.
  double min_side_contrast = 20.0;
  double side_reach_per_radius = 0.1;  ///< see min_side_contrast
  /// A hypothesis replaces the rough circle only when its coverage exceeds the rough one's by
  /// this much, [0, 1].
  double min_gain = 0.05;
};

/// Addition: the circle near rough whose outline the edge points agree on best. Edge points in
/// the annulus the slacks allow are sampled three at a time (points whose gradients are not
/// radial to the circle through them are skipped); each circle is scored by the angular
/// coverage of the points within the band with a radial gradient, the best refitted by
/// fit_circle (Tukey) on its supporters. With min_side_contrast a supporter must have the
/// ball's colour inside and another outside. Arcs of seams or the edge of fingers
/// belong to other circles and cover few sectors of the outline, so they no longer pull it.
/// Returns rough (its score the coverage measured alike) when nothing beats it by min_gain;
/// nullopt without a usable rough circle. Deterministic (fixed seed).
std::optional<Circle> robust_outline(const EdgeMap& edges, const Circle& rough,
                                     const OutlineSearchParams& params);

/// Angular coverage of c by the edge points of edges within params' band that have a radial
/// gradient (as robust_outline scores its hypotheses), [0, 1].
double outline_coverage(const EdgeMap& edges, const Circle& c, const OutlineSearchParams& params);

}  // namespace stereoball::ball_detector
