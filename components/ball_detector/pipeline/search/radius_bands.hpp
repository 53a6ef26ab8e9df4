#pragma once
// The whole left eye searched again radius band by radius band, each band with its own
// accumulator peaks, and each circle's right partner box with only its own radii (README:
// radius bands).

#include <atomic>
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
