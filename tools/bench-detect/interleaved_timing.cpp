#include "interleaved_timing.hpp"

#include <algorithm>
#include <cstdio>

namespace stereoball::bench_detect {
namespace {

// Quantile q of v by rank floor(q * (size - 1)) (no interpolation: a time that was measured).
double rank_quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const auto at = v.begin() + static_cast<std::ptrdiff_t>(q * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), at, v.end());
  return *at;
}

}  // namespace

double upper_median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

int InterleavedTimes::rounds() const {
  return images() == 0 ? 0 : static_cast<int>(ms.front().front().size());
}

std::vector<double> InterleavedTimes::per_image_ms(int method) const {
  std::vector<double> out;
  for (const auto& rounds : ms[static_cast<std::size_t>(method)])
    out.push_back(upper_median(rounds));
  return out;
}

double InterleavedTimes::median_ms(int method) const {
  return upper_median(per_image_ms(method));
}

double InterleavedTimes::round_median_ms(int method, int round) const {
  std::vector<double> of_round;
  for (const auto& rounds : ms[static_cast<std::size_t>(method)])
    of_round.push_back(rounds[static_cast<std::size_t>(round)]);
  return upper_median(of_round);
}

InterleavedTimes time_interleaved(int methods, int images, int rounds, const TimedMethods& calls,
                                  const std::function<double()>& clock_ms) {
  methods = std::max(0, methods);
  images = std::max(0, images);
  rounds = std::max(1, rounds);
  InterleavedTimes t;
  t.ms.assign(
      static_cast<std::size_t>(methods),
      std::vector<std::vector<double>>(static_cast<std::size_t>(images),
                                       std::vector<double>(static_cast<std::size_t>(rounds))));
  for (int i = 0; i < images; ++i) {
    calls.start_image(i);
    for (int m = 0; m < methods; ++m) calls.run(m, i);  // warm-up: first-call allocations
    for (int r = 0; r < rounds; ++r)
      for (int step = 0; step < methods; ++step) {
        const int m = (r + step) % methods;
        const double t0 = clock_ms();
        calls.run(m, i);
        t.ms[static_cast<std::size_t>(m)][static_cast<std::size_t>(i)]
            [static_cast<std::size_t>(r)] = clock_ms() - t0;
      }
  }
  return t;
}

TimeRatio time_ratio(const InterleavedTimes& t, int a, int b) {
  TimeRatio out;
  const double b_ms = t.median_ms(b);
  if (t.images() == 0 || !(b_ms > 0.0)) return out;
  out.ratio = t.median_ms(a) / b_ms;
  std::vector<double> per_round;
  for (int r = 0; r < t.rounds(); ++r)
    if (const double rb = t.round_median_ms(b, r); rb > 0.0)
      per_round.push_back(t.round_median_ms(a, r) / rb);
  if (!per_round.empty()) {
    out.round_min = *std::min_element(per_round.begin(), per_round.end());
    out.round_max = *std::max_element(per_round.begin(), per_round.end());
  }
  const std::vector<double> ia = t.per_image_ms(a), ib = t.per_image_ms(b);
  std::vector<double> per_image;
  for (std::size_t i = 0; i < ia.size(); ++i)
    if (ib[i] > 0.0) per_image.push_back(ia[i] / ib[i]);
  out.image_p25 = rank_quantile(per_image, 0.25);
  out.image_p75 = rank_quantile(per_image, 0.75);
  return out;
}

std::string format_ratio(const TimeRatio& r) {
  char text[128];
  std::snprintf(text, sizeof text, "%.2f (rounds %.2f-%.2f, per image p25-p75 %.2f-%.2f)", r.ratio,
                r.round_min, r.round_max, r.image_p25, r.image_p75);
  return text;
}

}  // namespace stereoball::bench_detect
