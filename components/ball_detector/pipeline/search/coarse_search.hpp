#pragma once
// The first try of a wide frame's whole-frame search, coarse to fine (core/coarse_to_fine.hpp):
// the left eye votes reduced to about coarse_to_fine.target_width_px, the circles of the whole
// radius range of those votes (and, if they pair only weakly, of each radius band too) are
// refined on the full-resolution edges, and radii too small for the reduced eye are voted for
// at full width (README: coarse to fine). When that pairs nothing (or only weakly), the frame
// is searched at full width as without it.

#include <opencv2/core.hpp>

#include <atomic>
#include <optional>
#include <utility>
#include <vector>

#include "ball_detector/core/coarse_to_fine.hpp"
#include "ball_detector/core/p2p_detector.hpp"
#include "ball_detector/pipeline/detector_params.hpp"
#include "stereo/core/sphere_outline.hpp"

namespace stereoball::ball_detector {

struct SearchTools;

/// Accumulator peaks the reduced eye's searches (whole range, each band) examine: a reduced
/// peak costs a full-resolution refinement as well.
constexpr int kCoarsePeaksExamined = 8;
/// Circles each radius band of the reduced eye passes on to the full-resolution refinement.
constexpr std::size_t kCoarseBandCircles = 4;

/// The reduced left eye's equipment for one calibration (SearchTools::coarse).
struct CoarseSearch {
  int level = 0;              ///< pyramid level of the left eye's votes (0 = full width: off)
  RadiusSplit split;          ///< the radius range between the reduced eye and full width
  PixelToPixelParams params;  ///< the reduced eye's detector settings (its pixels)
  std::optional<PixelToPixelDetector> detector;      ///< votes on the reduced left eye
  std::optional<PixelToPixelDetector> fine_path;     ///< radii below the reduced eye's, full width
  cv::Mat reduced_left;                              ///< the reduced rectified left eye
  std::vector<PixelToPixelDetector> band_detectors;  ///< the reduced eye's radius bands
  /// Coarse to fine by radius (BallDetectorParams::coarse_by_radius, a frame not wider than the
  /// target at level 1): the whole range's radii the reduced eye resolves are its, the smaller
  /// ones the full-width radius bands' only, and nothing is searched at full width after it.
  bool by_radius = false;
  /// By radius: the full-width left edges halved for the reduced eye's votes (buffers reused).
  EdgeMap halved_edges;

  /// Sets the level and detectors for frames image_width_px wide with the pipeline's (scaled)
  /// params; off when the frame is not wider than the target or no radius suits the reduced eye.
  void set_up(const BallDetectorParams& params, int image_width_px,
              const std::optional<stereo::PinholeCamera>& left_camera);
  /// Whether the whole-frame search tries the reduced eye first.
  bool on() const { return level > 0; }
};

/// The whole rectified left eye (tools.rect_left) reduced and voted on (coarse.on() only): the
/// left detector then holds the full-resolution edges only; false for an invalid image.
bool cast_reduced_left_votes(SearchTools& tools);

/// By radius (coarse.by_radius), after the left detector's find_edges(rect_left): those edges
/// halved (halve_edge_map) and voted on by the reduced eye; false for an invalid image.
bool cast_halved_left_votes(SearchTools& tools);

/// The circles of one coarse try's reduced votes refined at full width, in two steps (README:
/// coarse to fine on wide frames): the whole radius range's first; the radius bands' only when
/// asked for (when the whole range's circles give no strong pair). Each reduced circle is
/// refined once, however often it is asked for. Lives for one frame's coarse try.
class CoarseLeftCircles {
 public:
  /// For the votes cast_reduced_left_votes(tools) has just cast; tools must outlive this.
  explicit CoarseLeftCircles(SearchTools& tools);
  /// The same, its parts run by run (run_tasks_in_turn inside a task of tools.run_tasks, beside
  /// the radius bands' tasks: the node's runner would run them in turn there anyway).
  CoarseLeftCircles(SearchTools& tools, TaskRunner run) : tools_(tools), run_(std::move(run)) {}
  /// The whole radius range's circles refined, with the fine path's: best first, at most
  /// max_candidates_per_eye.
  std::vector<Circle> whole_range();
  /// The whole range's and each radius band's circles (kCoarseBandCircles a band) refined,
  /// with the fine path's: best first, at most max_candidates_per_eye.
  std::vector<Circle> with_bands();

 private:
  // reduced refined at full width (refine_coarse_circles, one at a time, so a circle asked for
  // again is not refined again), ranked with the fine path's circles.
  std::vector<Circle> refined_with_fine_path(const std::vector<Circle>& reduced);
  // The whole range's reduced circles (voted once).
  const std::vector<Circle>& whole_reduced();
  // Each of reduced not refined yet refined into refined_, and the fine path's circles into
  // fine_ if not searched yet: as tasks of run_.
  void refine_new(const std::vector<Circle>& reduced);

  SearchTools& tools_;
  TaskRunner run_;                            // runs this frame's parts: peaks, bands, refinements
  std::optional<std::vector<Circle>> whole_;  // the whole range's reduced circles
  std::optional<std::vector<Circle>> fine_;   // the fine path's circles
  // Each reduced circle refined so far and what it gave (empty: dropped).
  std::vector<std::pair<Circle, std::vector<Circle>>> refined_;
};

/// By radius: the left detector's lines (the window rules over its full-resolution edges, which
/// do not depend on the radii) made for the full-width radius bands, only the fine path's short
/// rays plotted; the detector then refines over its whole radius range again. False for no edges.
bool cast_full_width_lines(SearchTools& tools);

/// CoarseLeftCircles(tools).with_bands(): the circles of the reduced eye's votes (the whole
/// radius range's and each radius band's) refined at full width, with the fine path's.
std::vector<Circle> coarse_left_circles(SearchTools& tools);

}  // namespace stereoball::ball_detector
