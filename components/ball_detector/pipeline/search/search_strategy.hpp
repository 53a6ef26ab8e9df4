#pragma once
// The searches of one stereo frame behind one interface: each takes the frame's inputs (a
// const FrameState), the frame's scratch and the pipeline's reusable equipment (SearchTools),
// and returns what it found as a value (SearchOutcome). StereoPipeline::step runs them in order.

#include <opencv2/core.hpp>

#include <cstdint>
#include <optional>
#include <vector>

#include "ball_detector/core/circle.hpp"
#include "ball_detector/core/p2p_detector.hpp"
#include "ball_detector/pipeline/pairing.hpp"

namespace stereoball::ball_detector {

struct SearchTools;

/// Which search of a frame gave its answer.
enum class SearchPath {
  kExpectedOutlines,  ///< the prior's predicted outlines refined in each eye (no voting)
  kPriorWindow,       ///< voting in the box around the prior
  kWholeFrame,        ///< voting over the whole left eye
  kRadiusBands,       ///< the whole left eye again, radius band by radius band
  /// the colour seeds' outlines, or near a prior its expected outline, on the images with
  /// their brightness removed, in both eyes
  kBrightnessFree,
};

/// Short name of a search path ("expected_outlines", ...).
const char* to_string(SearchPath path);

/// What one frame gives every search; read-only. The images outlive the frame's step().
struct FrameState {
  const cv::Mat& left_raw;             ///< the left frame as received (BGR or grey), for colours
  const cv::Mat& left_channel;         ///< the left detector input (raw, or rectified already)
  const cv::Mat& right_channel;        ///< the right detector input (raw, or rectified already)
  bool rectified = false;              ///< the channels are rectified already (no LUT)
  std::optional<PositionPrior> prior;  ///< where the tracker expects the ball (metres)
  std::int64_t stamp_ns = 0;           ///< capture time, ns
  PairingContext ctx;                  ///< the frame's pairing geometry (motion_radii included)
};

/// What the searches of one frame hand on to later ones; lives for one step().
struct FrameScratch {
  cv::Rect prior_box;       ///< the left box around the prior, rectified px (near-prior searches)
  SearchHints prior_hints;  ///< the left detector's hints in prior_box
  bool bands_due = false;   ///< the whole-frame search also searches the left eye's radius bands
  int band = -1;            ///< ... only this one of them (wrapping; -1 = every band)
  /// the left eye's circles band by band (whole frame, when bands_due and nothing paired)
  std::optional<std::vector<Circle>> band_left;
  std::vector<Circle> colour_seeds;  ///< the whole-frame search's colour seeds, left rectified px
};

/// What one search found: its pairing and the candidates it paired (rectified px, best first).
struct SearchOutcome {
  PairingResult pairing;
  std::vector<Circle> left;
  std::vector<Circle> right;
  int rejected_by_colour = 0;  ///< left circles the followed ball's appearance rejected
  SearchPath path = SearchPath::kWholeFrame;  ///< the search that gave it

  /// Whether the pairing found a ball.
  bool found() const { return pairing.status == PairingStatus::kFound; }
  /// Whether it found a ball within prior's gate (metres).
  bool found_near(const PositionPrior& prior) const {
    return found() && cv::norm(pairing.best->position_m - prior.position_m) <= prior.gate_m;
  }
};

/// One search path of a frame.
class SearchStrategy {
 public:
  virtual ~SearchStrategy() = default;
  /// The search's outcome on frame, or nullopt when it does not apply (or, for a search that
  /// counts only within the prior's gate, found nothing there).
  virtual std::optional<SearchOutcome> run(const FrameState& frame, FrameScratch& scratch,
                                           SearchTools& tools) const = 0;
};

}  // namespace stereoball::ball_detector
