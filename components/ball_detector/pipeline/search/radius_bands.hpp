#pragma once
// The whole left eye searched again radius band by radius band, each band with its own
// accumulator peaks, and each circle's right partner box with only its own radii (README:
// radius bands).

#include <atomic>
#include <optional>
#include <utility>
#include <vector>

#include "ball_detector/pipeline/search/predicted_partner.hpp"
#include "ball_detector/pipeline/search/search_strategy.hpp"
#include "ball_detector/pipeline/search/search_tools.hpp"

namespace stereoball::ball_detector {

/// Ratio of a radius band's largest to smallest radius.
constexpr double kRadiusBandRatio = 2.5;

/// The bands of radii min..max (px) searched one at a time: up to a third of image_rows (README:
/// radius bands), each kRadiusBandRatio wide, neighbours overlapping by 10 % (a circle on a
/// boundary is whole in one of them).
std::vector<SearchHints> radius_bands(double min_radius_px, double max_radius_px, int image_rows);

/// found (best first) without the circles a better one of the same place and size (centres
/// within separation_px, radii within 20 %) precedes.
std::vector<Circle> best_of_each_place(const std::vector<Circle>& found, double separation_px);

/// The left detector's last image (whole, its own thresholds) searched again band by band, the
/// bands as tasks of tools.run_tasks; stops early (result unused) once *stop is set. Best first.
/// With only >= 0, band only (modulo their number) alone.
std::vector<Circle> detect_left_in_bands(SearchTools& tools, const std::atomic<bool>* stop,
                                         int only = -1);

/// detect_left_in_bands(tools, stop, only) in parts, for a caller that spreads a lost ball's
/// frame evenly over several cores: each band's votes and peaks (vote(b), one task per band),
/// then every band's peaks refined (refine(i), one task per peak), then circles(): the same
/// circles, bit for bit. The left detector's edges and lines are only read meanwhile.
class LeftBandParts {
 public:
  /// The bands to search, each with its detector.
  LeftBandParts(SearchTools& tools, int only);
  /// How many bands there are (vote() tasks).
  int bands() const { return static_cast<int>(bands_.size()); }
  /// Band b's votes over its radii and their peaks.
  void vote(int b);
  /// After every vote(): the peaks of all bands, refine() tasks (band by band, peak order).
  int peaks();
  /// The i-th of peaks() refined.
  void refine(int i);
  /// The bands' circles after every refine(): best first, one per place.
  std::vector<Circle> circles() const;

 private:
  SearchTools& tools_;
  std::vector<SearchHints> bands_;
  std::vector<std::optional<int>> peaks_;          // per band: nullopt = no circle there
  std::vector<std::vector<PeakCircles>> refined_;  // per band, per peak
  std::vector<std::pair<int, int>> tasks_;         // refine() task -> (band, peak)
};

/// How many radius bands the calibration's left eye has.
int radius_band_count(const SearchTools& tools);

/// scratch.band_left (or the bands searched now) paired with the right eye searched in each
/// circle's partner box (the whole frame's thresholds); its outcome whether or not it pairs.
class RadiusBandSearch : public SearchStrategy {
 public:
  std::optional<SearchOutcome> run(const FrameState& frame, FrameScratch& scratch,
                                   SearchTools& tools) const override;

 private:
  PredictedPartner pairing_;
};

}  // namespace stereoball::ball_detector
