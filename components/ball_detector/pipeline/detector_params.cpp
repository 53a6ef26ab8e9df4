#include "ball_detector/pipeline/detector_params.hpp"

#include <algorithm>
#include <cmath>

#include "common/util/enum_names.hpp"

namespace stereoball::ball_detector {

namespace {

// The rows are string literals: a name's data() ends in a NUL.
constexpr util::EnumName<DetectorInput> kDetectorInputNames[] = {
    {DetectorInput::kGrey, "grey"},    {DetectorInput::kSaturation, "saturation"},
    {DetectorInput::kValue, "value"},  {DetectorInput::kRed, "red"},
    {DetectorInput::kGreen, "green"},  {DetectorInput::kBlue, "blue"},
    {DetectorInput::kColour, "colour"}};

}  // namespace

const char* to_string(DetectorInput input) {
  return util::name_of(kDetectorInputNames, input, "grey").data();
}

std::optional<DetectorInput> parse_detector_input(const std::string& text) {
  return util::value_of(kDetectorInputNames, text);
}

namespace {

using params::at;
using params::flag;
using params::list;
using params::number;
using P = BallDetectorParams;
using P2P = PixelToPixelParams;
using A = AppearanceParams;

std::string input_word(DetectorInput input) {
  return to_string(input);
}
DetectorInput input_of(const std::string& word) {
  return parse_detector_input(word).value_or(DetectorInput::kGrey);
}

// The detector's and the appearance model's own rules (min_radius_px < max_radius_px...), on
// what the pipeline hands them.
Status cross_check(const P& p) {
  if (auto e = p.detector_params().validate(); !e) return Error{"p2p." + e.error()};
  if (auto e = p.appearance.validate(); !e) return Error{e.error()};
  return {};
}

std::vector<params::Field<P>> pipeline_fields() {
  return {
      number("ball.diameter_m", at(&P::ball_diameter_m), 0.22, {0.001, 5.0}, "m",
             "true ball diameter (the simulator's ball: radius 0.11 m)"),
      number("epipolar.tolerance_px", at(&P::epipolar_tolerance_px), 2.0, {0.0, 100.0}, "px",
             "largest abs(y_left - y_right) of a stereo pair, rectified (paper: 2)"),
      number("epipolar.ball_speed_mps", at(&P::epipolar_ball_speed_mps), 4.0, {0.0, 50.0}, "m/s",
             "unsynchronised eyes: fastest ball motion between the two exposures; rows may differ "
             "by tolerance_px plus speed x skew / ball radius of the outline radius (0 = off)"),
      number("epipolar.skew_ns", at(&P::epipolar_skew_ns), -1, {-1, 1'000'000'000}, "ns",
             "time between the eyes' exposures: -1 = from each frame's capture stamps, >= 0 = "
             "this (stills and sources whose stamps do not tell)"),
      number("size.max_relative_error", at(&P::size_max_relative_error), 0.15, {0.001, 10.0}, "",
             "accepted abs(r - r_expected) / r_expected at the triangulated depth"),
      number("floor.camera_height_m", at(&P::floor_camera_height_m), 0.30, {0.0, 10.0}, "m",
             "left camera's optical centre above the floor (simulator rig: 0.30)"),
      number("floor.camera_pitch_rad", at(&P::floor_camera_pitch_rad), 0.20, {-1.57, 1.57}, "rad",
             "left camera pitched down (simulator rig: 0.20)"),
      number("floor.tolerance_m", at(&P::floor_tolerance_m), 0.10, {0.0, 10.0}, "m",
             "reject pairs whose centre is farther from the resting height (0 = off: bouncing "
             "balls)"),
      number("image_limit.max_width_px", at(&P::max_image_width_px), 1920, {16, 16384}, "px",
             "larger stereo/calibration samples are refused before anything is allocated"),
      number("image_limit.max_height_px", at(&P::max_image_height_px), 1080, {16, 16384}, "px",
             "see image_limit.max_width_px"),
      number("working_width_px", at(&P::working_width_px), 1280, {0, 16384}, "px",
             "frames wider than this are shrunk (area) by the smallest whole factor that brings "
             "them to it, with the calibration, before anything else; positions are reported "
             "in the frame's own pixels (0 = every frame at its own size)"),
      number("max_candidates_per_eye", at(&P::max_candidates_per_eye), 5, {1, 50}, "",
             "Pixel-to-Pixel circles kept per eye"),
      flag("right_eye_partner_boxes", at(&P::right_eye_partner_boxes), true,
           "search the right eye only where a ball-sized partner of a left circle can be"),
      number("size.dominance_margin", at(&P::dominance_margin), 0.1, {0.0, 1.0}, "",
             "a found pair is withdrawn when a pair of larger outlines scoring this much higher, "
             "radii agreeing, fails the size check; unsynchronised eyes only (0 = off)"),
      flag("balance_radii", at(&P::balance_radii), true,
           "a found pair whose outline radii disagree beyond what the two views explain has the "
           "eye with the smaller refitted at the radius the other implies, centre only"),
      flag("predicted_partner.enabled", at(&P::predicted_partner), true,
           "a left circle no right circle pairs with: look along its epipolar line for the "
           "outline its ball makes in the right eye"),
      number("predicted_partner.min_inside_fraction", at(&P::predicted_partner_min_inside_fraction),
             0.2, {0.0, 1.0}, "", "that outline counts with this much of it in the right image"),
      number("track_prior.gate_m", at(&P::track_prior_gate_m), 0.3, {0.0, 10.0}, "m",
             "pairs this close to where ball/track expects the ball win over better-scoring "
             "pairs elsewhere (0 = off)"),
      number("track_prior.max_age_ns", at(&P::track_prior_max_age_ns), 500'000'000,
             {0, 10'000'000'000}, "ns", "older tracks are not used"),
      number("track_prior.min_inside_fraction", at(&P::prior_min_inside_fraction), 0.3, {0.0, 1.0},
             "", "there, a ball cut by the image border counts with this much of it inside"),
      flag("track_prior.window", at(&P::prior_window), true,
           "search first only where the prior says (whole frame if not found there)"),
      flag("track_prior.seeded", at(&P::prior_seeded), true,
           "there, first refine the outlines the prior predicts in each eye (no voting; the "
           "box is searched by voting if they pair nothing)"),
  };
}

std::vector<params::Field<P>> appearance_fields() {
  const A core;  // the model's own defaults are the pipeline's
  return {
      flag("appearance.enabled", at(&P::appearance, &A::enabled), core.enabled,
           "learn the followed ball's colour (hue-saturation histogram) while the tracker "
           "follows it"),
      number("appearance.min_similarity", at(&P::appearance, &A::min_similarity),
             core.min_similarity, {0.0, 1.0}, "",
             "left circles whose colours lie in the learnt ones less than this (containment) are "
             "rejected"),
      number("appearance.learn_rate", at(&P::appearance, &A::learn_rate), core.learn_rate,
             {0.001, 1.0}, "", "weight of each new sample once learnt"),
      number("appearance.frames_to_learn", at(&P::appearance, &A::frames_to_learn),
             core.frames_to_learn, {1, 1000}, "frames",
             "samples before it ranks and rejects anything"),
      number("appearance.forget_after_ns", at(&P::appearance, &A::forget_after_ns),
             core.forget_after_ns, {0, 3'600'000'000'000}, "ns",
             "a loss longer than this forgets it (the next ball may look different)"),
  };
}

std::vector<params::Field<P>> colour_seed_fields() {
  using C = ColourSeedParams;
  const C core;
  const auto in = [](auto member) { return at(&P::colour_seeds, member); };
  return {
      flag("colour_seeds.enabled", in(&C::enabled), core.enabled,
           "in a whole-frame search, regions of outstanding colour seed left candidates the "
           "votes missed (refined and scored on the edges like any other)"),
      number("colour_seeds.max_seeds", in(&C::max_seeds), core.max_seeds, {1, 50}, "",
             "the largest such regions refined per frame"),
      number("colour_seeds.min_chroma", in(&C::min_chroma), core.min_chroma, {0.0, 255.0},
             "grey levels", "a region's chroma (max - min of B, G, R) must exceed this"),
      number("colour_seeds.spread_factor", in(&C::spread_factor), core.spread_factor, {0.0, 100.0},
             "", "... and the image's median chroma by this many robust sigmas"),
      number("colour_seeds.rare_fraction", in(&C::rare_fraction), core.rare_fraction, {0.0, 0.5},
             "",
             "... or have a colour (8 levels per channel) covering less than this fraction of "
             "the image and a chroma at least its median (0 = off)"),
      flag("colour_seeds.chroma_outlines", in(&C::chroma_outlines), core.chroma_outlines,
           "when nothing pairs, the seeds' outlines (and a track's expected outline) are "
           "searched again in both eyes on the images with their brightness removed (a hue step "
           "the floor's brightness texture drowns)"),
  };
}

std::vector<params::Field<P>> interior_depth_fields() {
  using I = InteriorDepthParams;
  const I core;
  const auto in = [](auto member) { return at(&P::interior_depth, member); };
  return {
      flag("interior_depth.enabled", in(&I::enabled), core.enabled,
           "reject a found pair whose textured inside matches between the eyes at another depth "
           "than its outline (a round pattern on a surface, not a ball)"),
      number("interior_depth.min_texture", in(&I::min_texture), core.min_texture, {0.0, 255.0},
             "grey levels", "insides with less texture (standard deviation) are not matched"),
      number("interior_depth.min_match", in(&I::min_match), core.min_match, {0.0, 1.0}, "",
             "the inside's best match elsewhere (normalised cross-correlation) must reach this"),
      number("interior_depth.min_margin", in(&I::min_margin), core.min_margin, {0.0, 2.0}, "",
             "... and beat its best match at the ball's own depths by this"),
  };
}

std::vector<params::Field<P>> outline_refit_fields() {
  using O = OutlineRefitParams;
  using S = OutlineSearchParams;
  const O core;
  const auto in = [](auto member) { return at(&P::outline_refit, member); };
  const auto search = [](auto member) { return at(&P::outline_refit, &O::search, member); };
  return {
      flag("outline_refit.enabled", in(&O::enabled), core.enabled,
           "a found pair's outlines are fitted again in both eyes to the edge arcs that agree "
           "(fingers and seams no longer pull them)"),
      number("outline_refit.radius_slack", search(&S::radius_slack), core.search.radius_slack,
             {0.0, 1.0}, "", "refitted radius within this fraction of the first fit's"),
      number("outline_refit.centre_slack", search(&S::centre_slack), core.search.centre_slack,
             {0.0, 1.0}, "",
             "refitted centre within this fraction of the radius of the first fit's"),
      number("outline_refit.min_gain", search(&S::min_gain), core.search.min_gain, {0.0, 1.0}, "",
             "a refit replaces the first fit when it covers this much more of its circle"),
      number("outline_refit.min_side_contrast", search(&S::min_side_contrast),
             core.search.min_side_contrast, {0.0, 442.0}, "colour levels",
             "an edge point supports a refit only if the colour just inside is this much nearer "
             "the ball's than the colour just outside (a seam has the ball on both sides; 0 = "
             "off)"),
      number("outline_refit.hypotheses", search(&S::hypotheses), core.search.hypotheses,
             {1, 100000}, "", "circles through three sampled edge points tried per eye"),
      flag("outline_refit.withdraw_unpaired", in(&O::withdraw_unpaired), core.withdraw_unpaired,
           "a pair whose refitted outlines do not pair (rows, size) is withdrawn"),
  };
}

std::vector<params::Field<P>> coarse_to_fine_fields() {
  using C = CoarseToFineParams;
  const C core;
  const auto in = [](auto member) { return at(&P::coarse_to_fine, member); };
  return {
      number("coarse_to_fine.target_width_px", in(&C::target_width_px), 640, {0, 16384}, "px",
             "the whole-frame search of a wider frame first votes on the left eye reduced by "
             "powers of two to about this width and refines each circle found there on the "
             "full-resolution edges; if those pair nothing, the frame is searched at full width "
             "(0 = off: every search at full width)"),
      number("coarse_to_fine.min_pair_score", at(&P::coarse_min_pair_score), 0.65, {0.0, 1.0}, "",
             "a pair of the reduced eye's circles scoring less is left to the full-width "
             "search"),
      flag("coarse_to_fine.by_radius", at(&P::coarse_by_radius), false,
           "frames not wider than target_width_px: the whole-frame search votes on the halved "
           "left eye's edges (the full-width ones halved) for the radii of "
           "min_coarse_radius_px there and up (refined at full width) and leaves the smaller "
           "ones to the full-width radius bands; no full-width whole-range search"),
      number("coarse_to_fine.min_coarse_radius_px", in(&C::min_coarse_radius_px),
             core.min_coarse_radius_px, {0.1, 1000.0}, "px",
             "smallest radius searched on the reduced image, its pixels; smaller radii of the "
             "range are searched at full width"),
      number("coarse_to_fine.max_refine_shift", in(&C::max_refine_shift), core.max_refine_shift,
             {0.0, 1.0}, "radii",
             "a reduced-image circle whose full-resolution refinement moves its centre or "
             "changes its radius by more than this is dropped (another outline; 0 = off)"),
  };
}

std::vector<params::Field<P>> p2p_fields() {
  const P2P core;  // the detector's own defaults, where the pipeline keeps them
  const auto p2p = [](auto member) { return at(&P::p2p, member); };
  return {
      params::choice("input", at(&P::input), DetectorInput::kColour,
                     {"colour", "grey", "saturation", "value", "red", "green", "blue"}, input_word,
                     input_of,
                     "image P2P runs on (colour: edges from the channel that changes most at each "
                     "pixel; the others are expert overrides)"),
      list("p2p.k_values", p2p(&P2P::k_values), std::vector<int>{3, 5}, {1, 31}, "px",
           "half window sizes k (window 2k+1); k = 3 adds the votes of small and patterned "
           "balls"),
      number("p2p.min_radius_px", p2p(&P2P::min_radius_px), core.min_radius_px, {0.0, 4000.0}, "px",
             "smallest radius searched"),
      number("p2p.max_radius_px", p2p(&P2P::max_radius_px), 250.0, {1.0, 4000.0}, "px",
             "largest radius searched (a ball 0.4 m away is ~170 px)"),
      number("p2p.min_separation_px", p2p(&P2P::min_separation_px), core.min_separation_px,
             {0.0, 4000.0}, "px",
             "closest two candidates of one eye and of about one size (radii within 20 %) may be"),
      number("p2p.min_score", p2p(&P2P::min_score), core.min_score, {0.0, 1.0}, "",
             "candidates below this score (circumference coverage) are dropped"),
      number("p2p.rescue_weak_from", p2p(&P2P::rescue_weak_from), core.rescue_weak_from, {0.0, 1.0},
             "",
             "candidates scoring from this to min_score are refitted robustly (a ball's outline "
             "that patterns or floor lines pulled the fit off); >= min_score = off"),
      number("p2p.clutter_ring_per_radius",
             at(&P::p2p, &P2P::refine_params, &RefineParams::clutter_ring_per_radius), 0.1,
             {0.0, 1.0}, "",
             "a circle's score loses the edge coverage of the cleaner of the circles this "
             "fraction of its radius larger and smaller (texture covers both; 0 = off)"),
      number("p2p.clutter_min_radius_px",
             at(&P::p2p, &P2P::refine_params, &RefineParams::clutter_min_radius_px), 30.0,
             {0.0, 4000.0}, "px",
             "the clutter rings weigh in from this radius, fully at twice it (a wider scoring "
             "band covers texture by chance)"),
      number("p2p.max_peaks_examined", p2p(&P2P::max_peaks_examined), core.max_peaks_examined,
             {1, 1000}, "", "accumulator peaks scored as candidates per eye, strongest first"),
      number("p2p.edge_min_threshold", at(&P::p2p, &P2P::edge, &EdgeParams::min_high_threshold),
             core.edge.min_high_threshold, {1.0, 1000.0}, "",
             "floor of the Canny high threshold, Sobel abs(dx)+abs(dy) units (4 per grey level): "
             "sensor noise only, the threshold itself follows each image"),
      number("p2p.min_inside_fraction",
             at(&P::p2p, &P2P::refine_params, &RefineParams::min_inside_fraction),
             core.refine_params.min_inside_fraction, {0.0, 1.0}, "",
             "a circle cut by the image border needs this much of it inside to count"),
      number("p2p.reference_width_px", at(&P::p2p_reference_width_px), 640, {0, 16384}, "px",
             "image width k_values and the pixel lengths above are chosen for; wider images get "
             "them scaled by width / this (same scene window per k; 0 = as configured)"),
      flag("p2p.perspective_outline", at(&P::perspective_outline), true,
           "score circles against the ellipse a sphere images as off the optical axis (false: "
           "as circles, the paper)"),
  };
}

params::FieldTable<P> make_table() {
  params::FieldTable<P> t{pipeline_fields(), cross_check};
  for (const auto& part : {appearance_fields(), colour_seed_fields(), interior_depth_fields(),
                           outline_refit_fields(), coarse_to_fine_fields(), p2p_fields()}) {
    t.fields.insert(t.fields.end(), part.begin(), part.end());
  }
  return t;
}

}  // namespace

SB_PARAMS_TABLE(BallDetectorParams, detector_fields, make_table)

PixelToPixelParams BallDetectorParams::detector_params() const {
  PixelToPixelParams p = p2p;
  p.max_circles = max_candidates_per_eye;
  // Colour edges show every panel and stripe boundary of a two-colour ball where it meets the
  // outline, which orientation isolation cuts off (stereoball bench tracking, built-in scenes,
  // input colour: 96.93 -> 98.07 % accepted). A channel chosen for the ball hides them, and there
  // it changed 3 of 3165 frames for the worse (input red: 98.55 -> 98.45 %): off.
  p.isolate_by_orientation = input == DetectorInput::kColour;
  return p;
}

PixelToPixelParams scaled_to_width(const PixelToPixelParams& p2p, int reference_width_px,
                                   int image_width_px) {
  if (reference_width_px <= 0 || image_width_px <= reference_width_px) return p2p;
  const double f = static_cast<double>(image_width_px) / reference_width_px;
  PixelToPixelParams out = p2p;
  for (int& k : out.k_values) k = std::clamp(static_cast<int>(std::lround(k * f)), 1, 31);
  // In steps of whole k: a width a little above the reference keeps its settings exactly.
  if (out.k_values == p2p.k_values) return p2p;
  out.min_radius_px *= f;
  out.max_radius_px *= f;
  out.min_separation_px *= f;
  out.refine_params.clutter_min_radius_px *= f;
  return out;
}

}  // namespace stereoball::ball_detector
