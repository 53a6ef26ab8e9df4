#pragma once
// Times of several methods on the same images measured interleaved (per image every method in
// turn, round after round), so a machine that slows down or speeds up meanwhile slows every
// method alike; the ratio of two methods' medians and its spread. No clock of its own: the
// caller passes one (pure logic, testable).

#include <functional>
#include <string>
#include <vector>

namespace stereoball::bench_detect {

/// What time_interleaved measured: ms[m][i][r] is method m on image i in round r.
struct InterleavedTimes {
  std::vector<std::vector<std::vector<double>>> ms;
  /// Method m's median over rounds on each image.
  std::vector<double> per_image_ms(int method) const;
  /// Method m's median over images of its per-image medians (the figure compared).
  double median_ms(int method) const;
  /// Method m's median over images of round r's times alone.
  double round_median_ms(int method, int round) const;
  int methods() const { return static_cast<int>(ms.size()); }
  int images() const { return ms.empty() ? 0 : static_cast<int>(ms.front().size()); }
  int rounds() const;
};

/// The callbacks time_interleaved drives: start_image(i) readies every method for image i
/// (untimed: detectors made), run(m, i) runs method m once on image i (the part timed).
struct TimedMethods {
  std::function<void(int image)> start_image;
  std::function<void(int method, int image)> run;
};

/// Per image: start_image, one untimed warm-up run of every method, then `rounds` rounds each
/// running every method once, timed by clock_ms (ms, any origin). Round r starts with method
/// r mod methods: each method goes first equally often, so what running first costs or saves
/// (caches, clock ramp) falls on all. methods, images >= 0; rounds >= 1.
InterleavedTimes time_interleaved(int methods, int images, int rounds, const TimedMethods& calls,
                                  const std::function<double()>& clock_ms);

/// Method a's median time over method b's (median_ms), with its spread: the same ratio of
/// each round's medians alone (lowest, highest) and the quartiles of the per-image ratios.
struct TimeRatio {
  double ratio = 0.0;
  double round_min = 0.0, round_max = 0.0;
  double image_p25 = 0.0, image_p75 = 0.0;
};

/// a over b on the images both ran; zeros when there is no image or b's times are zero.
TimeRatio time_ratio(const InterleavedTimes& t, int a, int b);

/// Element at rank size/2 of v (the upper median for an even size, as the bench's other
/// medians); 0 for an empty v.
double upper_median(std::vector<double> v);

/// "ratio (rounds lo-hi, per image p25-p75)" for a printed line.
std::string format_ratio(const TimeRatio& r);

}  // namespace stereoball::bench_detect
