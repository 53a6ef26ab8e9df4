#pragma once
// Scoring of a real stereo set: the truth file (one row per pair: rectified ball centre and
// radius per eye, row offset, depth, flags) and each pair's detection against it. Pure: no DDS,
// no files (the caller reads the text), no clocks.

#include <cmath>
#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "common/util/result.hpp"

namespace stereoball::real_stereo {

/// Why a pair is left out of the figures (reported separately, not in the denominator).
enum class Exclusion { kNone, kNoRadius, kUnusable };

/// One row of a truth file, in the rectified pixels of the set's calibration at its own size.
struct TruthRow {
  std::string pair;                ///< pair id (column `pair`), unique in the file
  std::string left;                ///< left image file name (column `left`), in left/
  std::string right;               ///< right image file name (column `right`), in right/
  double left_cx = 0;              ///< rect_left_cx, px
  double left_cy = 0;              ///< rect_left_cy, px
  double left_r = 0;               ///< rect_left_r, px (NaN: no radius)
  double right_cx = 0;             ///< rect_right_cx, px
  double right_cy = 0;             ///< rect_right_cy, px
  double right_r = 0;              ///< rect_right_r, px (NaN: no radius)
  double dy_px = 0;                ///< dy_mean: left row minus right row, px
  double z_m = 0;                  ///< Z_m: depth of the ball's centre, metres (NaN: unknown)
  std::vector<std::string> flags;  ///< column `flag`, split at '|' and ';'
  std::size_t line = 0;            ///< line in the truth file (1 = header)

  /// Why the row is not scored, kNone when it is.
  Exclusion exclusion() const;
  /// Whether the detection's depth is checked against z_m.
  bool depth_checked() const;
  bool has_flag(const std::string& flag) const;
};

/// Parses a truth CSV (header line naming the columns; see README.md for the required ones).
/// name is the file in error messages: "NAME:LINE: what is wrong".
Result<std::vector<TruthRow>> parse_truth(const std::string& text, const std::string& name);

/// The truth of a set played at another width: centres scaled as pixel centres,
/// (x + 0.5) factor - 0.5, radii by factor; dy_px is kept (the |dy| bands are defined in the
/// truth file's pixels).
TruthRow scaled(const TruthRow& row, double factor);

/// What the detector said about one pair (the fields of ball/detection the scorer uses).
struct Detection {
  bool found = false;    ///< status FOUND
  std::string status;    ///< status name, e.g. "FOUND", "NO_CANDIDATE"
  std::string reason;    ///< the detector's reason text
  double left_x_px = 0;  ///< left circle centre, rectified px
  double left_y_px = 0;
  double left_r_px = 0;
  double z_m = 0;                ///< position_m[2], metres
  double processing_ms = 0;      ///< detector time for the frame, ms
  double cpu_ms = std::nan("");  ///< in-process only: the thread's CPU time for it, ms
};

/// Outcome of one pair.
enum class Verdict { kCorrect, kWrong, kMissed, kExcluded };

/// |dy_mean| bands of the report, px of the truth file (at its own image size).
enum class Band { kWithin2, k2To10, kOver10 };
const char* band_name(Band band);
Band band_of(double dy_px);

/// Scoring rules: centre within max(min_centre_px, centre_per_radius * r), depth within
/// depth_fraction of Z_m where the truth's depth is consistent.
struct ScoreRules {
  double min_centre_px = 6.0;
  double centre_per_radius = 0.35;
  double depth_fraction = 0.05;
};

/// One pair's score.
struct PairScore {
  TruthRow truth;  ///< as scored (scaled to the played width)
  Band band = Band::kWithin2;
  Verdict verdict = Verdict::kMissed;
  Exclusion exclusion = Exclusion::kNone;
  Detection detection;
  double centre_error_px = 0;  ///< |found left centre - truth| (FOUND only)
  double depth_error = 0;      ///< (z - Z_m) / Z_m (FOUND with a known Z_m)
  std::string why;             ///< what decided a wrong verdict
};

/// Scores one pair; an excluded truth row is kExcluded whatever the detection says. A pair with
/// no detection at all is a run error for the caller, never scored.
PairScore score_pair(const TruthRow& truth, const Detection& detection,
                     const ScoreRules& rules = {});

/// Correct/wrong/missed counts of a group of pairs.
struct Counts {
  int correct = 0;
  int wrong = 0;
  int missed = 0;
  int total() const { return correct + wrong + missed; }
  void add(Verdict v);
};

/// The figures of a run.
struct Summary {
  Counts overall;
  std::map<Band, Counts> bands;             ///< every band, even empty
  std::vector<std::string> excluded;        ///< "pair: why"
  std::map<std::string, int> miss_reasons;  ///< "STATUS: reason (numbers as #)" -> pairs
  std::size_t timed_frames = 0;             ///< frames with a processing time
  double median_ms = 0;                     ///< detector ms per frame (scored and excluded)
  double p90_ms = 0;
  std::size_t cpu_frames = 0;  ///< frames with a CPU time (in-process)
  double median_cpu_ms = 0;
  double p90_cpu_ms = 0;
};

/// Aggregates pair scores.
Summary summarize(const std::vector<PairScore>& pairs);

/// Whether a left-eye centre lies where the truth's ball is: within max(min_centre_px,
/// centre_per_radius * r) of its centre (score_pair's position rule, without depth).
bool centre_matches(const TruthRow& truth, double x_px, double y_px, const ScoreRules& rules = {});

/// A circle a reference method found in a left eye, in the truth's (played) pixels.
struct ReferenceCircle {
  double x_px = 0;
  double y_px = 0;
  double r_px = 0;
};

/// One frame of a reference method run beside the pipeline on the same decoded left eye.
struct ReferenceFrame {
  double detect_cpu_ms = 0;  ///< the method on the rectified left eye alone, thread CPU ms
  double decode_cpu_ms = 0;  ///< decoding the left eye and starting the right, thread CPU ms
  std::vector<ReferenceCircle> circles;  ///< its circles, best first
};

/// What a reference method achieved over a run, beside the pipeline's own figures.
struct ReferenceSummary {
  std::size_t frames = 0;            ///< frames it ran on
  double median_detect_ms = 0;       ///< its CPU time on one eye
  double median_decode_ms = 0;       ///< the frames' decode
  double median_frame_ms = 0;        ///< decode + its time, per frame (the least a frame costs)
  double median_pipeline_ratio = 0;  ///< median over frames of pipeline CPU / (decode + its time)
  int scored = 0;                    ///< pairs scored (not excluded) that it ran on
  int ball_among_circles = 0;        ///< ... whose ball centre is one of its circles' (one eye)
};

/// Summarises a reference run: frames[i] belongs to pairs[i] (nullopt: it did not run there).
ReferenceSummary summarize_reference(const std::vector<PairScore>& pairs,
                                     const std::vector<std::optional<ReferenceFrame>>& frames,
                                     const ScoreRules& rules = {});

/// A reason with every number replaced by '#', so misses group by kind.
std::string reason_kind(const std::string& status, const std::string& reason);

const char* verdict_name(Verdict v);
const char* exclusion_name(Exclusion e);

}  // namespace stereoball::real_stereo
