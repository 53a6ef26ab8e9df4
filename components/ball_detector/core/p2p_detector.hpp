#pragma once
// The Pixel-to-Pixel circle detector (paper section III) with the additions the system needs:
// several circles, sub-pixel centre, radius, a [0, 1] score and several window sizes k.

#include "ball_detector/core/circle.hpp"
#include "ball_detector/core/circle_fit.hpp"
#include "ball_detector/core/edge_map.hpp"
#include "ball_detector/core/p2p_rules.hpp"  // SB_WIDE_WINDOWS: whether the wide-window members exist
#include "ball_detector/core/voting.hpp"
#include "common/util/result.hpp"

#include <algorithm>
#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace stereoball::ball_detector {

/// Parameters of the Pixel-to-Pixel detector.
struct PixelToPixelParams {
  std::vector<int> k_values = {
      5};                      ///< half window sizes, each in [1, 31]; several = multi-k (addition)
  EdgeParams edge;             ///< edge-map step
  int box_size_px = 5;         ///< accumulator smoothing window (odd), pixels
  double min_radius_px = 4.0;  ///< votes start this far along each line, pixels
  double max_radius_px = 120.0;  ///< votes stop this far along each line, pixels
  int max_circles = 5;           ///< most circles returned (addition)
  /// Closest two returned centres of circles of about one size may be (addition), pixels:
  /// circles whose radii differ by kSameCircleRadiusRatio of the larger or more are kept
  /// around one centre (a striped ball's cap and its outline).
  double min_separation_px = 10.0;
  static constexpr double kSameCircleRadiusRatio = 0.2;
  double min_score = 0.55;          ///< circles scoring below are dropped (addition), [0, 1]
  int min_peak_votes = 12;          ///< smallest smoothed peak examined (votes in the box)
  double min_relative_peak = 0.15;  ///< peaks below this fraction of the strongest are ignored
  /// Accumulator peaks turned into scored candidates (addition), strongest first. More than
  /// max_circles: a large ball outline collects fewer votes than small round texture on it
  /// (its arcs are flatter), yet outscores that texture once refined and scored.
  int max_peaks_examined = 16;
  /// Addition: a window failing the count rule is judged again on the edge points 8-connected
  /// to its centre (the arc through O), so texture or a line merely passing through the window
  /// does not silence an arc. Off = the paper's rule exactly.
  bool isolate_arc = true;
  /// Addition (speed, detect() and circles_of_votes() only): > 0 = the peaks, strongest first,
  /// stop being examined once this many in a row gave no circle (the rest are weaker still:
  /// texture). 0 = every peak up to max_peaks_examined, [0, 1000].
  int stop_after_missed_peaks = 0;
  /// Arc isolation is tried only on windows holding at most this many times 2k+1 points:
  /// denser windows are texture, where the flood fill costs time and rarely isolates an arc
  /// (addition), [1, 64].
  double isolate_max_points_factor = 3.0;
  /// Addition (with isolate_arc): when the arc through O is still joined by another edge (a
  /// panel or stripe boundary of a two-colour ball meeting its outline, a floor seam touching
  /// it), it is isolated once more among the edge points whose gradient direction lies within
  /// about 35 degrees of O's (8 orientation bins, O's and its two neighbours): a boundary
  /// meeting the outline at a large angle is cut off there, a smooth arc is not.
  bool isolate_by_orientation = true;
  bool refine = true;          ///< sub-pixel least-squares refinement (addition)
  RefineParams refine_params;  ///< refinement and scoring options
  /// Addition (with refine): the circles kept are refined once more from a wider first band
  /// (kPolishFirstBandPx) with the robust fit (kPolishRobustFloorPx). Colour edges see a
  /// patterned ball's panel and stripe boundaries, which near the rim run parallel to the
  /// outline a pixel or two inside it; least squares let them pull fits inwards by up to 2 px
  /// (p95, the simulator's panelled ball). Only the kept circles: the few that matter.
  bool polish = true;
  static constexpr double kPolishFirstBandPx = 4.0;
  static constexpr double kPolishRobustFloorPx = 0.6;
  /// Addition (with refine): a candidate whose least-squares refinement scores at least this
  /// but below min_score is refined once more as polish does (wider first band, robust fit) and
  /// kept if that reaches min_score. A ball whose panel or stripe boundaries, or a floor line
  /// crossing it, pull the least-squares circle off its outline scores low for the pull, not
  /// for a missing outline; texture has no outline for the robust fit to find. In [0, 1];
  /// >= min_score = off.
  double rescue_weak_from = 0.4;
  /// Addition (speed, the single-image detect(image) only): candidates are found on the image
  /// halved (every step a quarter of the pixels; radii, separation and each k halved, k
  /// rounded up, so a k sees the same scene window either way), those scoring
  /// at least coarse_min_score there are refined and scored at full resolution on the edges of
  /// a window around each (its own edge thresholds), and kept if they reach min_score. The
  /// calls with thresholds or hints (the stereo node's) and redetect are unchanged. Off = the
  /// whole image at full resolution.
  bool coarse_to_fine = false;
  double coarse_min_score = 0.45;  ///< a halved-image candidate needs this score, [0, 1]
  /// A halved-image peak is refined only when its voters lie around it, covering at least this
  /// fraction of the circle's angular sectors (a ball's outline votes from all sides; a blob
  /// of texture from one), [0, 1].
  double coarse_min_voted_coverage = 0.2;
  /// Addition (speed, with coarse_to_fine): > 0 = the halved image turns at most this many
  /// accumulator peaks into candidates (otherwise max(max_peaks_examined, max_circles), as every
  /// candidate goes on to full resolution). 0 = off, [0, 1000].
  int coarse_max_peaks_examined = 0;
  /// Addition (with coarse_to_fine, detect(image) only): circles of radius below this are
  /// searched at full resolution with fine_k_values, the others coarse to fine from this radius
  /// up (a circle of a few pixels halved is below what the halved search finds); the two lists
  /// are merged. 0 = off (coarse to fine for every radius), px.
  double fine_below_radius_px = 0.0;
  std::vector<int> fine_k_values = {3};  ///< k of that full-resolution search, each in [1, 31]
  /// Addition (speed, with fine_below_radius_px): > 0 = the full-resolution search of the small
  /// radii turns at most this many accumulator peaks into candidates and keeps at most this
  /// many circles (its peaks are otherwise max(max_peaks_examined, max_circles)); its circles
  /// are merged with the coarse-to-fine search's as before. 0 = off, [0, 1000].
  int fine_max_peaks_examined = 0;
  /// Addition (speed, with fine_below_radius_px): isolate_arc in the full-resolution search of
  /// the small radii (arc isolation is most of its voting time). False = the count rule alone
  /// there; the coarse-to-fine search keeps isolate_arc.
  bool fine_isolate_arc = true;
  /// Addition (speed, with fine_below_radius_px): true = the full-resolution search of the
  /// small radii drops a candidate after its first refinement round when that round's widest
  /// band covers less than min_score of it (RefineParams::give_up_below, as the coarse-to-fine
  /// search's full-resolution stage does), so weak peaks cost one round and are not rescued
  /// (rescue_weak_from) there. False = every candidate fully refined.
  bool fine_give_up = false;
  /// Addition (speed, with fine_below_radius_px): true = the coarse-to-fine search of the other
  /// radii refines and scores its halved-image candidates on the full-resolution edge map the
  /// small-radius search made of the whole image (its thresholds), instead of an edge map of
  /// their windows with the windows' own thresholds: one full-resolution edge step per image.
  /// False = each window's own edges.
  bool fine_shared_edges = false;
  /// Addition (speed, with fine_below_radius_px): stop_after_missed_peaks in the full-resolution
  /// search of the small radii (0 = its own value), [0, 1000].
  int fine_stop_after_missed_peaks = 0;

  /// Success, or an error naming the first bad field and its allowed range.
  Status validate() const;
  /// fine_below_radius_px's full-resolution search of the small radii.
  PixelToPixelParams small_circle_search() const;
  /// fine_below_radius_px's coarse-to-fine search of the other radii.
  PixelToPixelParams large_circle_search() const;
};

/// A range of circle radii, pixels.
struct RadiusRange {
  double min_px = 0.0;
  double max_px = 0.0;
};

/// What a caller that knows what to expect (a tracked ball) can tell detect().
struct SearchHints {
  RadiusRange radii{0.0, 1e9};  ///< radii to search, intersected with the params' range
  /// Fraction of a circle that must lie inside the image (RefineParams::min_inside_fraction);
  /// negative = the params' value.
  double min_inside_fraction = -1.0;
  /// Addition: centres up to this far outside the image are voted for (the accumulator is
  /// padded by it on every side), pixels. A ball cut by the image border has its centre outside
  /// when less than half of it is in view; an image-sized accumulator cannot find it. 0 = off;
  /// at most the largest radius searched.
  int centre_margin_px = 0;
};

/// One edge point that cast a vote: where it is and which way its line goes (unit vector).
struct Voter {
  float x = 0.0f;
  float y = 0.0f;
  float ux = 0.0f;
  float uy = 0.0f;
};

/// The voters that may lie in a band of rows, found without scanning them all. Voters come in
/// raster order of their edge points, one run per k, so within a run y is sorted up to a few
/// pixels: the run's prefix maximum and suffix minimum of y are sorted and bound it by binary
/// search. Visits keep the voters' order (sums over them then run as over a full scan).
class VoterRows {
 public:
  VoterRows() = default;
  /// Indexes voters (which the visits must be given again, unchanged).
  explicit VoterRows(const std::vector<Voter>& voters);
  /// Calls f(voter) for every voter with y in [y_lo, y_hi] (and possibly a few others).
  template <typename F>
  void for_each(const std::vector<Voter>& voters, double y_lo, double y_hi, F&& f) const {
    for_each_range(y_lo, y_hi, [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) f(voters[i]);
    });
  }
  /// The same voters as index ranges: f(begin, end) per run, in the visits' order.
  template <typename F>
  void for_each_range(double y_lo, double y_hi, F&& f) const {
    for (const auto& run : runs_) {
      const auto first =
          std::lower_bound(prefix_max_.begin() + run.begin, prefix_max_.begin() + run.end, y_lo);
      const auto last =
          std::upper_bound(suffix_min_.begin() + run.begin, suffix_min_.begin() + run.end, y_hi);
      const auto begin = static_cast<std::size_t>(first - prefix_max_.begin());
      const auto end = static_cast<std::size_t>(last - suffix_min_.begin());
      if (begin < end) f(begin, end);
    }
  }

 private:
  static constexpr float kNewRunDropPx = 64.0f;
  struct Run {
    std::size_t begin, end;
  };
  std::vector<Run> runs_;
  std::vector<float> prefix_max_, suffix_min_;
};

/// Runs task(0) .. task(n - 1), possibly at the same time, and returns once all are done; each
/// task touches only its own state. The caller's: the core starts no threads.
using TaskRunner = std::function<void(int n, const std::function<void(int)>& task)>;

/// How the voting of cast_votes() runs: in turn (shares <= 1 or no runner), or in shares tasks
/// of run, each voting on its part of the rows of every k into its own accumulator, added after
/// (saturating, as one map saturates): the same accumulator, voters and lines either way.
struct VoteTasks {
  TaskRunner run;  ///< empty = in turn
  int shares = 1;  ///< tasks the votes are split into, [1, kMaxVoteShares]
  static constexpr int kMaxVoteShares = 8;
};

/// The circles one accumulator peak gives, best first: none, one, or one and a circle of another
/// size nested around it (CandidateOptions::nested_circles).
using PeakCircles = std::vector<Circle>;

/// Candidates turned into circles for any 2D line-voting detector: consistent voters give the
/// radius, least-squares refinement gives the sub-pixel centre, angular coverage the score.
struct CandidateOptions {
  double min_radius_px = 4.0;
  double max_radius_px = 120.0;
  double line_tolerance_px = 3.5;  ///< a voter's line passes this close to the peak, pixels
  double min_separation_px = 10.0;
  double min_score = 0.5;
  int max_circles = 5;
  bool refine = true;
  RefineParams refine_params;
  bool polish = false;            ///< PixelToPixelParams::polish
  double rescue_weak_from = 1.0;  ///< PixelToPixelParams::rescue_weak_from
  /// true: a peak whose circle is found also gives a circle of another size around about its
  /// centre when enough of its voters lie at that distance (a striped ball's cap and outline,
  /// whose peaks merge).
  bool nested_circles = false;
  /// > 0: a peak whose voters (the edge points whose lines pass it, within the radius range)
  /// lie in less than this fraction of 16 angular sectors around it is not refined.
  double min_voted_coverage = 0.0;
  /// true: the seed radius is the distance most voters share per unit of circumference (a
  /// small circle's voters outnumber, per pixel of its outline, the lines of other edges that
  /// merely pass its centre), and the ring-of-edge-points second seed is not tried; false: the
  /// voters' median distance, then the ring seed for weak candidates.
  bool voter_mode_radius = false;
};

/// The CandidateOptions every line-voting detector's params fill alike (PixelToPixelParams,
/// GradientVotingParams: box, separation, score, count, refinement) for the radii searched;
/// the options only Pixel-to-Pixel uses keep their defaults.
template <typename VotingParams>
CandidateOptions candidate_options_of(const VotingParams& params, RadiusRange radii) {
  CandidateOptions opt;
  opt.min_radius_px = radii.min_px;
  opt.max_radius_px = radii.max_px;
  opt.line_tolerance_px = 0.5 * params.box_size_px + 1.0;
  opt.min_separation_px = params.min_separation_px;
  opt.min_score = params.min_score;
  opt.max_circles = params.max_circles;
  opt.refine = params.refine;
  opt.refine_params = params.refine_params;
  return opt;
}

/// Pixel-to-Pixel: thin edge map -> per-window chord rules -> concave-side lines -> box filter
/// -> peaks -> refined, scored circles sorted by decreasing score.
class PixelToPixelDetector final : public CircleDetector {
 public:
  /// Params must be valid (see PixelToPixelParams::validate); invalid values are clamped.
  explicit PixelToPixelDetector(const PixelToPixelParams& params);
  std::vector<Circle> detect(const cv::Mat& bgr_or_grey) override;
  /// detect() with the edge thresholds and pre-blur decision of another edge map (e.g. the
  /// other eye's full image) instead of this image's own: for crops, whose statistics depend on
  /// what they happen to hold.
  std::vector<Circle> detect(const cv::Mat& bgr_or_grey, const EdgeThresholds& thresholds);
  /// Same with hints: only radii in hints.radii (votes are plotted over that span only:
  /// faster, and nothing of another size can win), and its border rule.
  std::vector<Circle> detect(const cv::Mat& bgr_or_grey, const EdgeThresholds& thresholds,
                             const SearchHints& hints);
  /// Addition (tracking): circles where the caller expects them, without voting. Each seed (a
  /// predicted outline a few pixels at most off the ball's, image coordinates) is refined on the
  /// image's edges by the robust fit from the polish's wider first band, polished as kept circles
  /// are, and kept if it scores min_score with a radius in hints.radii; best first, as detect()
  /// returns them. Where a tracked ball's position is predicted the voting and its peaks are
  /// most of the search's time, and a seed the prediction misses gives nothing (the caller then
  /// searches by voting).
  std::vector<Circle> detect_at_seeds(const cv::Mat& bgr_or_grey, const EdgeThresholds& thresholds,
                                      const SearchHints& hints, std::span<const Circle> seeds);
  /// The edge step alone on a whole image (its own thresholds, as cast_votes() makes them), no
  /// votes: for circles found some other way (refine_seeds), e.g. on a reduced copy of the image
  /// (coarse_to_fine.hpp). False for an invalid image.
  bool find_edges(const cv::Mat& bgr_or_grey);
  /// detect_at_seeds() on the edges of the last image (cast_votes() or a detect()), with its
  /// radius range: for seeds found some other way than by this detector's votes.
  std::vector<Circle> refine_seeds(std::span<const Circle> seeds) const;
  /// Circles already refined on this detector's edges ranked as refine_seeds() ranks its own:
  /// best first, none within min_separation_px of a better one of about its size, at most
  /// max_circles (no refinement).
  std::vector<Circle> keep_best_separated(std::vector<Circle> found) const;
  /// Addition (colour seeds): detect_at_seeds() on bgr (CV_8UC3) with its brightness removed
  /// (compute_brightness_free_edge_map in edge_map.hpp), with thresholds measured on that image
  /// itself (bgr is a box around the seeds: its statistics are the ball's and its surroundings'). A
  /// ball whose rim differs from the floor in hue but hardly in brightness, on a floor whose
  /// brightness texture sets the frame's thresholds, has its outline here. Empty for an image
  /// that is not colour.
  std::vector<Circle> detect_at_seeds_without_brightness(const cv::Mat& bgr,
                                                         const SearchHints& hints,
                                                         std::span<const Circle> seeds);
  /// detect(bgr_or_grey) in two halves, for a caller that runs other work beside the second:
  /// the edge step and the voting (false for an invalid image: nothing to find); after it,
  /// other detectors may redetect_from() this one while it runs circles_of_votes().
  /// tasks: how the voting runs (VoteTasks; the same votes either way).
  bool cast_votes(const cv::Mat& bgr_or_grey, const VoteTasks& tasks = {});
  /// cast_votes() on an edge map made elsewhere (halve_edge_map), swapped in: edges gets the
  /// previous map's buffers back; false (nothing voted) for an empty map.
  bool cast_votes_on_edges(EdgeMap& edges, const VoteTasks& tasks = {});
  /// cast_votes() of the last image (find_edges or cast_votes) on its edge map, without the
  /// edge step again: the same votes; false before any valid image.
  bool cast_votes_on_last_edges(const VoteTasks& tasks = {});
  /// cast_votes_on_last_edges() over hints' radii only: every line (the window rules do not
  /// depend on the radii) is kept for redetect, only the plotted rays are shorter.
  bool cast_votes_on_last_edges(const SearchHints& hints, const VoteTasks& tasks = {});
  /// refine_seeds() over the params' radii and inside fraction again after a search with hints
  /// (its votes, peaks, lines and edges kept).
  void forget_hints();
  /// The second half: the peaks of the last votes refined and scored, as detect() returns them
  /// (empty if the last cast_votes() had an invalid image).
  std::vector<Circle> circles_of_votes();
  /// circles_of_votes() in parts, for a caller that refines peaks on several cores: the peaks
  /// of the last votes (their number); refine_peak(i) for each i in [0, that), in any order or
  /// at once (it changes nothing); select_circles() of the results in peak order gives exactly
  /// circles_of_votes().
  int find_peaks_of_votes();
  PeakCircles refine_peak(int i) const;
  std::vector<Circle> select_circles(const std::vector<PeakCircles>& per_peak) const;
  /// detect() once more on the last image's edge map with other hints, without the edge step
  /// or the window rules (the lines they gave are plotted again over the new radii: the same
  /// image searched radius band by radius band); empty before the first image.
  std::vector<Circle> redetect(const SearchHints& hints);
  /// redetect() on source's last image: source's edge map and lines are only read, so several
  /// detectors can search bands of one image at once (source must not change meanwhile).
  /// Same circles as source.redetect(hints) given the same params and camera.
  std::vector<Circle> redetect_from(const PixelToPixelDetector& source, const SearchHints& hints);
  /// redetect_from() in parts, for a caller that refines the peaks on several cores: the votes
  /// over hints' radii and their peaks (their number), nullopt where redetect_from() returns no
  /// circle before any peak; then refine_peak(i) for each and select_circles() in peak order
  /// give exactly redetect_from()'s circles (source must not change until then).
  std::optional<int> peaks_from(const PixelToPixelDetector& source, const SearchHints& hints);
  const DetectionDiagnostics* diagnostics() const override;
  std::string name() const override { return "p2p"; }
  /// The rectified camera of the whole image (RefineParams::camera); nullopt = circles only.
  void set_camera(const std::optional<stereo::PinholeCamera>& camera) {
    params_.refine_params.camera = camera;
  }
  /// A reduced image's detector (coarse_to_fine.hpp): peaks whose voters cover less than
  /// min_voted_coverage of the sectors around them are not refined, and with voter_mode_radius
  /// a peak's seed radius is its voters' densest ring (CandidateOptions); defaults 0, false.
  void set_reduced_image_options(double min_voted_coverage, bool voter_mode_radius) {
    voted_coverage_gate_ = min_voted_coverage;
    voter_mode_radius_ = voter_mode_radius;
  }
  /// The settings in use (clamped as the constructor clamps them).
  const PixelToPixelParams& params() const { return params_; }
  /// Votes of the last image, before smoothing (CV_16U); padded by the hints' centre margin.
  const cv::Mat& raw_accumulator() const { return accumulator_; }
  /// The voters of the last image.
  const std::vector<Voter>& voters() const { return voters_; }
  /// Edge map of the last image.
  const EdgeMap& edge_map() const { return edges_; }
  /// Radii searched in the last image: the params' range, or the caller's hints within it.
  RadiusRange radius_range() const { return radii_; }

 private:
  // One line the window rules let vote: its start C (on the half-pixel grid, exact in float)
  // and its unnormalised direction, as plot_ray takes them.
  struct VoteLineAt {
    float cx = 0.0f, cy = 0.0f;
    int nx = 0, ny = 0;
  };
  // plot(): per vote line direction (nx, ny), its ray set-up and the voter's unit vector, made
  // on first use; a direction is a difference of window points, |nx|, |ny| <= direction_span_.
  struct LineDirection {
    RayDirection ray;
    float unit_x = 0.0f, unit_y = 0.0f;
    bool ready = false;
  };
  // One task's share of split votes (VoteTasks): its rows of each k, its own accumulator (the
  // first share's is accumulator_), and its lines and voters, k_ends[j] after k_values[j]'s.
  struct VoteShare {
    cv::Mat store, accumulator;
    std::vector<VoteLineAt> lines;
    std::vector<Voter> voters;
    std::vector<std::size_t> k_ends;
    std::int64_t rays_plotted = 0, increments = 0;
  };
  void vote(int k);
  // The lines of k's windows centred on rows [y_begin, y_end), in raster order, to
  // emit(cx, cy, nx, ny) (a VoteLineAt's fields).
  template <typename Emit>
  void vote_rows(int k, int y_begin, int y_end, Emit&& emit);
  // f(x, y) for every edge point of rows [y_begin, y_end) whose window of half size k lies in
  // the image, in raster order: the points vote_rows and vote_packed judge.
  template <typename F>
  void for_each_window_centre(int k, int y_begin, int y_end, F&& f) const;
  // The most points a window of n rows may hold for its arc to be isolated (0: isolation off).
  int isolate_max_points_of(int n) const;
  template <int k, typename Emit>
  void vote_packed(int y_begin, int y_end, Emit& emit);  // vote_rows() for k <= kPackedMaxK
  template <int k>
  bool isolate_packed(int x, int y, std::uint64_t window, std::uint64_t& arc);
#if SB_WIDE_WINDOWS
  template <int k, typename Emit>
  void vote_wide(int y_begin, int y_end, Emit& emit);  // vote_rows() for k <= kWideMaxK
  template <int k>
  bool isolate_wide(int x, int y, WideWindow window, WideWindow& arc);
#endif
  void plot(const VoteLineAt& line);
  void plot(const VoteLineAt& line, cv::Mat& accumulator, VoteShare& share);
  // plot()'s work into the given accumulator, its ray count (since zeroed), the increments, the
  // voters.
  void plot_into(const VoteLineAt& line, cv::Mat& accumulator, std::int64_t& rays_plotted,
                 std::int64_t& increments, std::vector<Voter>& voters);
  void vote_in_shares(const VoteTasks& tasks);
  // Per k, the rows bounding each of n shares (n + 1 each): about as many edge points each.
  std::vector<std::vector<int>> share_rows(int n) const;
  void vote_share(int s, const std::vector<std::vector<int>>& rows);
  void join_shares(int n);
  bool isolate_along_orientation(int x, int y, int k, std::span<const std::uint64_t> window,
                                 std::span<std::uint64_t> mask);
  void build_orientation_planes();
  std::vector<Circle> detect_on_edges();
  /// The edge step of detect(image, thresholds, hints) (false: nothing to search).
  bool edges_with_hints(const cv::Mat& bgr_or_grey, const EdgeThresholds& thresholds,
                        const SearchHints& hints);
  // The edge step's start: the hints taken, the last edge map forgotten; false when image or
  // the radius range leaves nothing to find.
  bool begin_edge_step(const cv::Mat& image, const SearchHints& hints);
  std::vector<Circle> detect_coarse_to_fine(const cv::Mat& image);
  // detect_coarse_to_fine's full-resolution stage on a full-resolution edge map of the whole
  // image (fine_shared_edges), or on its windows' own maps (null).
  std::vector<Circle> detect_coarse_to_fine(const cv::Mat& image, const EdgeMap* whole_edges);
  std::vector<Circle> detect_multi_scale(const cv::Mat& image);  // p2p_multi_scale.cpp
  std::optional<Circle> refine_in_window(const EdgeMap& edges, const cv::Rect& window,
                                         Circle seed) const;
  void vote_on_edges(const VoteTasks& tasks = {});
  std::vector<Circle> circles_on(const EdgeMap& edges);
  int peaks_on(const EdgeMap& edges);
  // redetect_from's votes: false where it finds nothing (no edges yet, an empty radius range).
  bool revote_from(const PixelToPixelDetector& source, const SearchHints& hints);
  void start(const std::optional<SearchHints>& hints);
  std::vector<Circle> circles_from_peaks();

  PixelToPixelParams params_;
  RadiusRange radii_;  // of the current image: the params' range or the caller's within it
  double min_inside_fraction_ = 0.5;  // of the current image
  int margin_px_ = 0;                 // of the current image: accumulator padding per side
  EdgeMap edges_;
  bool edges_ready_ = false;  // edges_ holds the last image's map (redetect may reuse it)
  bool votes_ready_ = false;  // the accumulator and voters hold the votes of edges_
  // Plane b: the edge points whose orientation bin is within the slack of bin b, built once
  // per image on the first orientation isolation (each point lies in up to (2k+1)^2 windows).
  std::array<BitImage, 8> near_orientation_;
  bool orientation_ready_ = false;
  cv::Mat accumulator_;
  std::int64_t rays_plotted_ = 0;  // into accumulator_ since it was zeroed
  const LineDirection& line_direction(int nx, int ny);
  // Every direction of the table made: line_direction then only reads it (tasks share it).
  void fill_directions();
  std::vector<LineDirection> directions_;
  int direction_span_ = 0;
  LineDirection direction_scratch_;  // a direction outside the table
  cv::Mat smoothed_;                 // box-filtered accumulator_, buffer kept across images
  std::vector<int> row_maxima_;      // smoothed_'s rows' largest values (box_filter)
  // The memory accumulator_ and smoothed_ are views of, kept when their size changes (the
  // margin follows each search's radii): no fresh pages to fault in per search.
  cv::Mat accumulator_store_, smoothed_store_;
  std::vector<Voter> voters_;
  std::vector<VoteLineAt> lines_;  // every line of edges_, in voting order (redetect replays)
  std::vector<VoteShare> shares_;  // split votes' shares (VoteTasks), buffers kept across images
  // The peaks being refined (find_peaks_of_votes), the edges and options they are refined with.
  std::vector<Peak> peaks_;
  const EdgeMap* peak_edges_ = nullptr;
  CandidateOptions candidate_options_;
  VoterRows voter_rows_;
  // coarse_to_fine: the detector of the halved image, the halved image and a window's edges.
  std::unique_ptr<PixelToPixelDetector> coarse_;
  // fine_below_radius_px: the full-resolution small-radius and coarse-to-fine large searches.
  std::unique_ptr<PixelToPixelDetector> small_, large_;
  cv::Mat half_;
  cv::Mat brightness_free_;           // detect_at_seeds_without_brightness's image, reused
  double voted_coverage_gate_ = 0.0;  // CandidateOptions::min_voted_coverage (a reduced one's)
  bool voter_mode_radius_ = false;    // CandidateOptions::voter_mode_radius (a reduced one's)
  EdgeMap window_edges_;
  mutable DetectionDiagnostics diag_;
  mutable bool peak_ratio_done_ = false;
};

/// Shared post-processing: peaks of a smoothed accumulator + voters -> scored circles
/// (circle_from_peak on each, then select_circles).
std::vector<Circle> circles_from_votes(const EdgeMap& edges, const std::vector<Voter>& voters,
                                       const std::vector<Peak>& peaks,
                                       const CandidateOptions& options);

/// One peak of circles_from_votes refined and scored; empty when it gives no circle (too few
/// voters, score or radius out of range). rows indexes voters.
PeakCircles circle_from_peak(const EdgeMap& edges, const std::vector<Voter>& voters,
                             const VoterRows& rows, const Peak& peak,
                             const CandidateOptions& options);

/// The circles circles_from_votes keeps of the peaks' circles (in peak order): best score
/// first, none within min_separation_px of a better one of about its size, at most max_circles;
/// then polished on edges when options.polish (PixelToPixelParams::polish).
std::vector<Circle> select_circles(const EdgeMap& edges, std::vector<Circle> found,
                                   const CandidateOptions& options);

}  // namespace stereoball::ball_detector
