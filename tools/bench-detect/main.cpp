// stereoball bench detect: deterministic synthetic suite (accuracy + timing), real images
// (timing), and labelled real photographs (accuracy + timing, settings tuned on one split and
// reported on the other) for Pixel-to-Pixel and the baselines, all in one run, one core.

#include "ball_detector/core/baselines.hpp"
#include "ball_detector/core/edge_map.hpp"
#include "ball_detector/core/evaluation.hpp"
#include "ball_detector/core/p2p_detector.hpp"
#include "ball_detector/core/synthetic.hpp"
#include "real_photos.hpp"

#include "common/util/bench_clock.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include "common/util/cli11.hpp"

#include <time.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace bd = stereoball::ball_detector;
namespace fs = std::filesystem;

namespace {

using Factory = std::function<std::unique_ptr<bd::CircleDetector>(cv::Size)>;

struct Method {
  std::string label;
  Factory make;
};

struct Tally {
  int tp = 0, fp = 0, fn = 0;
  std::vector<double> errors_px;
  std::map<cv::Size::value_type, std::vector<double>> synth_ms;  // keyed by width
  std::map<cv::Size::value_type, std::vector<double>> real_ms;
  std::map<std::string, std::array<int, 3>> per_kind;  // tp, fp, fn
};

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

double min_radius(cv::Size s) {
  return 0.025 * std::min(s.width, s.height);
}
double max_radius(cv::Size s) {
  return 0.2 * std::min(s.width, s.height);
}
double min_sep(cv::Size s) {
  return 0.04 * std::min(s.width, s.height);
}

bd::PixelToPixelParams p2p_params(cv::Size s, std::vector<int> ks) {
  bd::PixelToPixelParams p;
  p.k_values = std::move(ks);
  p.min_radius_px = min_radius(s);
  p.max_radius_px = max_radius(s);
  p.min_separation_px = min_sep(s);
  return p;
}

std::vector<Method> make_methods(bool with_cht, double cht_step_px) {
  std::vector<Method> m;
  m.push_back({"p2p k=5", [](cv::Size s) {
                 return std::make_unique<bd::PixelToPixelDetector>(p2p_params(s, {5}));
               }});
  m.push_back({"p2p k=5 paper rule", [](cv::Size s) {
                 // The window count rule exactly as the paper states it (no arc isolation).
                 auto p = p2p_params(s, {5});
                 p.isolate_arc = false;
                 return std::make_unique<bd::PixelToPixelDetector>(p);
               }});
  m.push_back({"p2p k=3,5,8", [](cv::Size s) {
                 return std::make_unique<bd::PixelToPixelDetector>(p2p_params(s, {3, 5, 8}));
               }});
  m.push_back({"p2p k=3,5,8,15", [](cv::Size s) {
                 return std::make_unique<bd::PixelToPixelDetector>(p2p_params(s, {3, 5, 8, 15}));
               }});
  m.push_back({"gradient", [](cv::Size s) {
                 bd::GradientVotingParams p;
                 p.min_radius_px = min_radius(s);
                 p.max_radius_px = max_radius(s);
                 p.min_separation_px = min_sep(s);
                 return std::make_unique<bd::GradientVotingDetector>(p);
               }});
  if (with_cht)
    m.push_back({"cht step=" + cv::format("%g", cht_step_px), [cht_step_px](cv::Size s) {
                   bd::ChtParams p;
                   p.min_radius_px = min_radius(s);
                   p.max_radius_px = max_radius(s);
                   p.min_separation_px = min_sep(s);
                   p.radius_step_px = cht_step_px;
                   return std::make_unique<bd::ChtDetector>(p);
                 }});
  for (double p2 : {20.0, 30.0, 45.0})
    m.push_back({cv::format("opencv p2=%g", p2), [p2](cv::Size s) {
                   bd::OpenCvHoughParams p;
                   p.param2 = p2;
                   p.blur_ksize = 5;
                   p.min_radius_px = min_radius(s);
                   p.max_radius_px = max_radius(s);
                   p.min_separation_px = min_sep(s);
                   return std::make_unique<bd::OpenCvHoughDetector>(p);
                 }});
  for (double p2 : {0.6, 0.75, 0.9})
    m.push_back({cv::format("opencv-alt p2=%g", p2), [p2](cv::Size s) {
                   bd::OpenCvHoughParams p;
                   p.alt = true;
                   p.dp = 1.5;
                   p.param1 = 300.0;
                   p.param2 = p2;
                   p.min_radius_px = min_radius(s);
                   p.max_radius_px = max_radius(s);
                   p.min_separation_px = min_sep(s);
                   return std::make_unique<bd::OpenCvHoughDetector>(p);
                 }});
  m.push_back({"edcircles", [](cv::Size s) {
                 bd::EdCirclesParams p;
                 p.min_radius_px = min_radius(s);
                 p.max_radius_px = max_radius(s);
                 p.min_separation_px = min_sep(s);
                 return std::make_unique<bd::EdCirclesDetector>(p);
               }});
  return m;
}

// The real-photograph families: each method with the settings tried on the tune split. The
// smallest radius is the label file's (every circle down to it is labelled; by default 2.5% of
// the shorter side); largest radius and separation follow the image size as in the synthetic
// suite; up to 100 circles an image (the most baselines accept; three photographs hold 53-70).
constexpr int kRealMaxCircles = 100;

// The multi-scale family's shared setting: voting with ks coarse to fine from fine_per_rmin x
// rmin up, k=3 at full resolution below it, band 0.035 r, up to kRealMaxCircles circles.
bd::PixelToPixelParams multi_scale_params(cv::Size s, double rmin, std::vector<int> ks,
                                          double fine_per_rmin, double score, double clutter,
                                          int peaks) {
  auto p = p2p_params(s, std::move(ks));
  p.min_radius_px = rmin;
  p.coarse_to_fine = true;
  p.fine_below_radius_px = fine_per_rmin * rmin;
  p.fine_k_values = {3};
  p.refine_params.band_per_radius = 0.035;
  p.min_score = score;
  p.refine_params.clutter_ring_per_radius = clutter;
  p.max_circles = kRealMaxCircles;
  p.max_peaks_examined = peaks;
  return p;
}

std::string k_list(const std::vector<int>& ks) {
  std::string out;
  for (int k : ks) out += (out.empty() ? "" : ",") + std::to_string(k);
  return out;
}

std::vector<stereoball::bench_detect::Family> real_families() {
  using stereoball::bench_detect::Family;
  std::vector<Family> f;
  // p2p coarse to fine (PixelToPixelParams::coarse_to_fine); k as at full resolution (halved
  // for the halved image).
  Family p2p{"p2p", {}};
  const std::vector<std::vector<int>> coarse_k_sets = {{3}, {5}, {3, 5}, {3, 5, 8}};
  for (const auto& ks : coarse_k_sets)
    for (double score : {0.35, 0.45, 0.55})
      for (double clutter : {0.0, 0.1})
        for (int peaks : {kRealMaxCircles / 2, 2 * kRealMaxCircles})
          for (bool polish : {true, false})
            for (double band : {0.025, 0.035})
              p2p.settings.push_back(
                  {cv::format("c2f k=%s score>=%.2f clutter=%.1f peaks=%d band=%.3fr%s",
                              k_list(ks).c_str(), score, clutter, peaks, band,
                              polish ? "" : " no-polish"),
                   [ks, score, clutter, peaks, polish, band](cv::Size s, double rmin) {
                     auto p = p2p_params(s, ks);
                     p.min_radius_px = rmin;
                     p.coarse_to_fine = true;
                     p.polish = polish;
                     p.refine_params.band_per_radius = band;
                     p.min_score = score;
                     p.refine_params.clutter_ring_per_radius = clutter;
                     p.max_circles = kRealMaxCircles;
                     p.max_peaks_examined = peaks;
                     return std::make_unique<bd::PixelToPixelDetector>(p);
                   }});
  // Multi-scale (PixelToPixelParams::fine_below_radius_px): radii below `fine` times the
  // smallest searched at full resolution with k = 3, the rest coarse to fine as above (a first
  // sweep on the tune split: min score 0.45 and clutter 0 lost everywhere, fine k = 2,3 never
  // beat k = 3, so the grid spends its settings on scores, clutter and peaks instead).
  for (const auto& ks : std::vector<std::vector<int>>{{3, 5}, {3, 5, 8}})
    for (double score : {0.5, 0.55, 0.6})
      for (double clutter : {0.1, 0.2})
        for (int peaks : {kRealMaxCircles / 2, 2 * kRealMaxCircles})
          for (bool polish : {true, false})
            for (double fine : {2.0, 3.0})
              p2p.settings.push_back(
                  {cv::format("multi fine<%.0fxrmin k=%s fine k=3 score>=%.2f clutter=%.1f "
                              "peaks=%d band=0.035r%s",
                              fine, k_list(ks).c_str(), score, clutter, peaks,
                              polish ? "" : " no-polish"),
                   [ks, fine, score, clutter, peaks, polish](cv::Size s, double rmin) {
                     auto p = multi_scale_params(s, rmin, ks, fine, score, clutter, peaks);
                     p.polish = polish;
                     return std::make_unique<bd::PixelToPixelDetector>(p);
                   }});
  // Multi-scale with a cheaper full-resolution search of the small radii (most of the
  // multi-scale time): fewer of its peaks examined (fine_max_peaks_examined), no arc isolation
  // there (fine_isolate_arc), weak candidates given up after one round (fine_give_up), around
  // the multi-scale grid's better settings.
  for (double score : {0.55, 0.6})
    for (double clutter : {0.1, 0.2})
      for (int fine_peaks : {0, kRealMaxCircles / 2})
        for (bool fine_isolate : {true, false})
          for (bool give_up : {false, true}) {
            if (fine_peaks == 0 && fine_isolate && !give_up) continue;  // the grid's above
            p2p.settings.push_back(
                {cv::format("multi fine<2xrmin k=3,5 fine k=3 fine-peaks=%d fine-isolate=%s "
                            "fine-give-up=%s score>=%.2f clutter=%.1f peaks=%d band=0.035r",
                            fine_peaks, fine_isolate ? "on" : "off", give_up ? "on" : "off", score,
                            clutter, kRealMaxCircles / 2),
                 [score, clutter, fine_peaks, fine_isolate, give_up](cv::Size s, double rmin) {
                   auto p = multi_scale_params(s, rmin, {3, 5}, 2.0, score, clutter,
                                               kRealMaxCircles / 2);
                   p.fine_max_peaks_examined = fine_peaks;
                   p.fine_isolate_arc = fine_isolate;
                   p.fine_give_up = give_up;
                   return std::make_unique<bd::PixelToPixelDetector>(p);
                 }});
          }
  // The chosen multi-scale setting's family made cheaper in its coarse-to-fine part: fewer
  // halved-image peaks turned into candidates (coarse_max_peaks_examined; otherwise
  // max(peaks, circles) = 100) and the candidates refined on the small-radius search's
  // whole-image edge map instead of their windows' own (fine_shared_edges).
  for (double score : {0.55, 0.6})
    for (double clutter : {0.1, 0.2})
      for (int coarse_peaks : {0, kRealMaxCircles / 4, kRealMaxCircles / 2})
        for (bool shared_edges : {false, true}) {
          if (coarse_peaks == 0 && !shared_edges) continue;  // the grid's above
          p2p.settings.push_back(
              {cv::format("multi fine<2xrmin k=3,5 fine k=3 fine-peaks=0 fine-isolate=on "
                          "fine-give-up=on coarse-peaks=%d shared-edges=%s score>=%.2f "
                          "clutter=%.1f peaks=%d band=0.035r",
                          coarse_peaks, shared_edges ? "on" : "off", score, clutter,
                          kRealMaxCircles / 2),
               [score, clutter, coarse_peaks, shared_edges](cv::Size s, double rmin) {
                 auto p =
                     multi_scale_params(s, rmin, {3, 5}, 2.0, score, clutter, kRealMaxCircles / 2);
                 p.fine_give_up = true;
                 p.coarse_max_peaks_examined = coarse_peaks;
                 p.fine_shared_edges = shared_edges;
                 return std::make_unique<bd::PixelToPixelDetector>(p);
               }});
        }
  // The chosen multi-scale setting with its small radii's peaks, strongest first, examined until
  // several in a row give nothing (fine_stop_after_missed_peaks), at the split or below it.
  for (int stop : {2, 3, 5, 10, 20})
    for (double fine : {2.0, 1.5})
      p2p.settings.push_back(
          {cv::format("scale fine<%.2fxrmin fine-stop=%d k=3,5 fine k=3 give-up coarse-peaks=50 "
                      "score>=0.55 clutter=0.2 peaks=50",
                      fine, stop),
           [stop, fine](cv::Size s, double rmin) {
             auto p = multi_scale_params(s, rmin, {3, 5}, fine, 0.55, 0.2, kRealMaxCircles / 2);
             p.fine_give_up = true;
             p.coarse_max_peaks_examined = kRealMaxCircles / 2;
             p.fine_stop_after_missed_peaks = stop;
             return std::make_unique<bd::PixelToPixelDetector>(p);
           }});
  // And at full resolution only: coarse to fine halves a 6 px circle to 3 px, below what the
  // halved search finds; the tune split decides which wins.
  for (const auto& ks : std::vector<std::vector<int>>{{5}, {3, 5}, {3, 5, 8}})
    for (double score : {0.45, 0.55})
      for (double clutter : {0.0, 0.1})
        for (bool polish : {true, false})
          p2p.settings.push_back(
              {cv::format("full k=%s score>=%.2f clutter=%.1f peaks=%d band=0.035r%s",
                          k_list(ks).c_str(), score, clutter, 2 * kRealMaxCircles,
                          polish ? "" : " no-polish"),
               [ks, score, clutter, polish](cv::Size s, double rmin) {
                 auto p = p2p_params(s, ks);
                 p.min_radius_px = rmin;
                 p.coarse_to_fine = false;
                 p.polish = polish;
                 p.refine_params.band_per_radius = 0.035;
                 p.min_score = score;
                 p.refine_params.clutter_ring_per_radius = clutter;
                 p.max_circles = kRealMaxCircles;
                 p.max_peaks_examined = 2 * kRealMaxCircles;
                 return std::make_unique<bd::PixelToPixelDetector>(p);
               }});
  f.push_back(p2p);
  const std::vector<std::vector<int>> k_sets = {{5}, {5, 8, 15}, {3, 5, 8, 15}};
  Family paper{"p2p paper rule", {}};
  for (const auto& ks : k_sets)
    paper.settings.push_back({"k=" + k_list(ks), [ks](cv::Size s, double rmin) {
                                auto p = p2p_params(s, ks);
                                p.min_radius_px = rmin;
                                p.isolate_arc = false;
                                p.max_circles = kRealMaxCircles;
                                p.max_peaks_examined = 2 * kRealMaxCircles;
                                return std::make_unique<bd::PixelToPixelDetector>(p);
                              }});
  f.push_back(paper);
  Family hough{"HOUGH_GRADIENT", {}};
  for (double p1 : {100.0, 200.0})
    for (double p2 : {20.0, 30.0, 45.0, 60.0})
      hough.settings.push_back(
          {cv::format("p1=%g p2=%g blur 5", p1, p2), [p1, p2](cv::Size s, double rmin) {
             bd::OpenCvHoughParams p;
             p.param1 = p1;
             p.param2 = p2;
             p.blur_ksize = 5;
             p.min_radius_px = rmin;
             p.max_radius_px = max_radius(s);
             p.min_separation_px = min_sep(s);
             p.max_circles = kRealMaxCircles;
             return std::make_unique<bd::OpenCvHoughDetector>(p);
           }});
  f.push_back(hough);
  Family alt{"HOUGH_GRADIENT_ALT", {}};
  for (double p1 : {150.0, 300.0})
    for (double p2 : {0.6, 0.75, 0.85, 0.9})
      alt.settings.push_back(
          {cv::format("dp=1.5 p1=%g p2=%g", p1, p2), [p1, p2](cv::Size s, double rmin) {
             bd::OpenCvHoughParams p;
             p.alt = true;
             p.dp = 1.5;
             p.param1 = p1;
             p.param2 = p2;
             p.min_radius_px = rmin;
             p.max_radius_px = max_radius(s);
             p.min_separation_px = min_sep(s);
             p.max_circles = kRealMaxCircles;
             return std::make_unique<bd::OpenCvHoughDetector>(p);
           }});
  f.push_back(alt);
  Family ed{"EDCircles", {}};
  for (int g : {10, 20, 30, 40})
    for (double ratio : {0.8, 0.9})
      ed.settings.push_back(
          {cv::format("grad=%d axis_ratio=%.1f", g, ratio), [g, ratio](cv::Size s, double rmin) {
             bd::EdCirclesParams p;
             p.gradient_threshold = g;
             p.min_axis_ratio = ratio;
             p.min_radius_px = rmin;
             p.max_radius_px = max_radius(s);
             p.min_separation_px = min_sep(s);
             p.max_circles = kRealMaxCircles;
             return std::make_unique<bd::EdCirclesDetector>(p);
           }});
  f.push_back(ed);
  return f;
}

// --setting METHOD=LABEL: METHOD keeps only the setting labelled LABEL. Returns an error naming
// the entry that is malformed or matches no method or setting, else "".
std::string fix_settings(const std::vector<std::string>& entries,
                         std::vector<stereoball::bench_detect::Family>& families) {
  for (const std::string& entry : entries) {
    const auto eq = entry.find('=');
    if (eq == std::string::npos) return "--setting '" + entry + "': expected METHOD=LABEL";
    const std::string method = entry.substr(0, eq), label = entry.substr(eq + 1);
    const auto family = std::find_if(families.begin(), families.end(),
                                     [&](const auto& f) { return f.name == method; });
    if (family == families.end()) return "--setting '" + entry + "': no method '" + method + "'";
    std::erase_if(family->settings, [&](const auto& st) { return st.label != label; });
    if (family->settings.empty())
      return "--setting '" + entry + "': " + method + " has no setting '" + label + "'";
  }
  return "";
}

using stereoball::bench::thread_cpu_ms;

double time_ms(bd::CircleDetector& det, const cv::Mat& img, std::vector<bd::Circle>* out) {
  const double t0 = thread_cpu_ms();
  auto found = det.detect(img);
  const double ms = thread_cpu_ms() - t0;
  if (out) *out = std::move(found);
  return ms;
}

std::vector<cv::Mat> load_real_images(const std::string& dir, std::vector<std::string>& names) {
  std::vector<cv::Mat> imgs;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return imgs;
  std::vector<fs::path> paths;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const auto ext = e.path().extension().string();
    if (ext == ".png" || ext == ".jpg") paths.push_back(e.path());
  }
  std::sort(paths.begin(), paths.end());
  for (const auto& p : paths) {
    cv::Mat m = cv::imread(p.string(), cv::IMREAD_COLOR);
    if (m.empty()) {
      std::fprintf(stderr, "stereoball-bench-detect: skipping unreadable '%s'\n", p.c_str());
      continue;
    }
    imgs.push_back(m);
    names.push_back(p.filename().string());
  }
  return imgs;
}

// Paper fig. 10/11: four circles of growing radius; the smoothed votes at each centre per k.
void k_selection_table() {
  const cv::Size size(352, 288);
  cv::Mat img(size, CV_8UC3, cv::Scalar(50, 60, 55));
  const std::vector<std::pair<cv::Point, int>> circles = {
      {{40, 60}, 6}, {{110, 200}, 14}, {{190, 80}, 30}, {{280, 190}, 60}};
  for (const auto& [c, r] : circles)
    cv::circle(img, c, r, cv::Scalar(40, 170, 230), cv::FILLED, cv::LINE_AA);
  std::printf("\nk selects circle size (paper fig. 10/11): smoothed votes at each centre\n");
  std::printf("%-6s", "k");
  for (const auto& [c, r] : circles) std::printf("  r=%-6d", r);
  std::printf("  strongest\n");
  for (int k : {3, 5, 8, 15}) {
    bd::PixelToPixelParams p;
    p.k_values = {k};
    p.max_radius_px = 100;
    bd::PixelToPixelDetector det(p);
    det.detect(img);
    const cv::Mat& acc = det.diagnostics()->accumulator;
    std::printf("%-6d", k);
    double best = -1;
    int best_r = 0;
    for (const auto& [c, r] : circles) {
      double v = 0;
      cv::minMaxLoc(acc(cv::Rect(c.x - 3, c.y - 3, 7, 7)), nullptr, &v);
      std::printf("  %-8.2f", v);
      if (v > best) {
        best = v;
        best_r = r;
      }
    }
    std::printf("  r=%d\n", best_r);
  }
}

// Median ms of the edge step alone at one size: the p2p edge map, and OpenCV's own grey +
// Canny (SIMD Sobel, non-maximum suppression and hysteresis in one call) as the fastest edge
// map at hand. No detector that starts from a full-image edge map can be faster than it.
struct EdgeFloor {
  std::vector<double> p2p_ms, opencv_ms;
};

void time_edge_step(const cv::Mat& image, EdgeFloor& floor) {
  static bd::EdgeMap edges;
  const bd::EdgeParams params;
  double t0 = thread_cpu_ms();
  bd::compute_edge_map(image, params, edges);
  floor.p2p_ms.push_back(thread_cpu_ms() - t0);
  t0 = thread_cpu_ms();
  cv::Mat grey, canny;
  cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  cv::Canny(grey, canny, 100.0, 300.0);
  floor.opencv_ms.push_back(thread_cpu_ms() - t0);
}

// Median ms at 640x480 of a method, synthetic and real (0 when it did not run).
std::pair<double, double> times_640(const std::vector<Method>& methods,
                                    const std::vector<Tally>& tallies, const std::string& label) {
  for (size_t mi = 0; mi < methods.size(); ++mi) {
    if (methods[mi].label != label) continue;
    const auto syn = tallies[mi].synth_ms.find(640);
    const auto real = tallies[mi].real_ms.find(640);
    return {syn == tallies[mi].synth_ms.end() ? 0.0 : median(syn->second),
            real == tallies[mi].real_ms.end() ? 0.0 : median(real->second)};
  }
  return {0.0, 0.0};
}

// The issue's speed target side by side: ALT over p2p, and ALT over the edge step alone.
void print_speed_ratios(const std::vector<Method>& methods, const std::vector<Tally>& tallies,
                        const EdgeFloor& syn, const EdgeFloor& real) {
  std::printf("\nEdge step alone at 640x480 (median ms): %-10s %8s\n", "synthetic", "real");
  std::printf("  p2p edge map                        %10.2f %8.2f\n", median(syn.p2p_ms),
              median(real.p2p_ms));
  std::printf("  OpenCV grey + cv::Canny(100, 300)   %10.2f %8.2f\n", median(syn.opencv_ms),
              median(real.opencv_ms));
  const auto alt = times_640(methods, tallies, "opencv-alt p2=0.9");
  if (alt.first <= 0.0) return;
  auto ratio = [](double a, double b) { return b > 0.0 ? a / b : 0.0; };
  std::printf(
      "ALT p2=0.9 time / that (the most any edge-map detector can gain on ALT): %.1fx "
      "synthetic, %.1fx real\n",
      ratio(alt.first, median(syn.opencv_ms)), ratio(alt.second, median(real.opencv_ms)));
  for (const std::string label : {"p2p k=5", "p2p k=5 paper rule", "p2p k=3,5,8,15"}) {
    const auto t = times_640(methods, tallies, label);
    if (t.first > 0.0)
      std::printf("ALT p2=0.9 time / %-18s at 640x480: %.2fx synthetic, %.2fx real\n",
                  label.c_str(), ratio(alt.first, t.first), ratio(alt.second, t.second));
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Benchmark every circle detector on a deterministic synthetic suite (precision, recall, "
      "F1 at IoU >= 0.8, median centre error) and on real images (timing only), one core."};
  int per_kind = 6;
  std::uint32_t seed = 1;
  std::string real_dir = SB_DEFAULT_REAL_DIR;
  bool no_cht = false;
  double cht_step = 2.0;
  std::string dump_dir;
  double min_iou = 0.8;
  std::string explain;
  std::vector<std::string> only;
  std::string labels_dir = SB_DEFAULT_LABELS_DIR;
  std::string project_root = SB_PROJECT_ROOT;
  int real_repeats = 3;
  bool no_synthetic = false, verbose_tuning = false, breakdown = false, detections = false;
  std::string settings_matching;
  std::vector<std::string> fixed_settings;
  std::string time_cap = "EDCircles";
  app.add_option("--per-kind", per_kind, "Synthetic scenes per kind and size (10 kinds)")
      ->capture_default_str()
      ->check(CLI::Range(1, 200));
  app.add_option("--seed", seed, "Suite seed (same seed = same images)")->capture_default_str();
  app.add_option("--real-dir", real_dir, "Folder of real images timed at both sizes")
      ->capture_default_str();
  app.add_flag("--no-cht", no_cht, "Skip the (slow) classic 3D CHT");
  app.add_option("--cht-step", cht_step, "CHT radius step, pixels")
      ->capture_default_str()
      ->check(CLI::Range(0.5, 20.0));
  app.add_option("--min-iou", min_iou, "IoU needed for a true positive")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--explain", explain,
                 "Print every miss and false positive of the method with this label prefix");
  app.add_option("--dump-dir", dump_dir, "Also write the synthetic images here (PNG)");
  app.add_option("--only", only,
                 "Run only the methods whose label starts with this (repeatable; for profiling: "
                 "ratios need the methods side by side in one run)");
  app.add_option("--labels-dir", labels_dir, "Folder of *.circles label files (real photographs)")
      ->capture_default_str();
  app.add_option("--project-root", project_root, "Label files name images relative to this")
      ->capture_default_str();
  app.add_option("--real-repeats", real_repeats, "Timed runs per labelled photograph (median)")
      ->capture_default_str()
      ->check(CLI::Range(1, 50));
  app.add_flag("--no-synthetic", no_synthetic,
               "Only the labelled real photographs (skip the synthetic suite and timing images)");
  app.add_flag("--verbose-tuning", verbose_tuning, "Print every setting's tune-split F1 and time");
  app.add_option("--settings-matching", settings_matching,
                 "Try only the settings whose label contains this (development: the choice is "
                 "then not the full sweep's)");
  app.add_option("--setting", fixed_settings,
                 "METHOD=LABEL: that method tries only the setting labelled exactly LABEL "
                 "(repeatable; for timing builds side by side: the choice is then not the "
                 "sweep's)");
  app.add_option("--time-cap", time_cap,
                 "Also choose Pixel-to-Pixel's best tune F1 among its settings no slower on the "
                 "tune split than this method's chosen setting (empty: off)")
      ->check(CLI::IsMember(
          {"", "p2p paper rule", "HOUGH_GRADIENT", "HOUGH_GRADIENT_ALT", "EDCircles"}))
      ->capture_default_str();
  app.add_flag("--detections", detections,
               "Print every circle each row's setting finds on every photograph (both splits; "
               "for diffing two builds, not for choosing settings)");
  app.add_flag("--tune-breakdown", breakdown,
               "Print each method's chosen setting's tune-split circles found by labelled radius "
               "and per image (the report split's are never printed)");
  CLI11_PARSE(app, argc, argv);
  cv::setNumThreads(1);

  const auto labelled = stereoball::bench_detect::load_labelled_images(labels_dir, project_root);
  if (const auto* e = std::get_if<std::string>(&labelled)) {
    std::fprintf(stderr, "stereoball-bench-detect: %s\n", e->c_str());
    return 1;
  }
  auto families = real_families();
  if (!settings_matching.empty())
    for (auto& f : families)
      std::erase_if(f.settings, [&](const stereoball::bench_detect::Setting& st) {
        return st.label.find(settings_matching) == std::string::npos;
      });
  if (const std::string error = fix_settings(fixed_settings, families); !error.empty()) {
    std::fprintf(stderr, "stereoball-bench-detect: %s\n", error.c_str());
    return 2;
  }
  if (!only.empty())
    std::erase_if(families, [&](const stereoball::bench_detect::Family& f) {
      return std::none_of(only.begin(), only.end(),
                          [&](const std::string& p) { return f.name.rfind(p, 0) == 0; });
    });
  if (no_synthetic) {
    stereoball::bench_detect::run_real_photo_table(families, std::get<0>(labelled), real_repeats,
                                                   min_iou, verbose_tuning, breakdown, time_cap,
                                                   detections);
    return 0;
  }
  const std::vector<cv::Size> sizes = {{352, 288}, {640, 480}};
  std::vector<std::string> real_names;
  const auto real = load_real_images(real_dir, real_names);
  if (real.empty())
    std::fprintf(stderr, "stereoball-bench-detect: no real images in '%s'; timing synthetic only\n",
                 real_dir.c_str());
  auto methods = make_methods(!no_cht, cht_step);
  if (!only.empty()) {
    std::erase_if(methods, [&](const Method& m) {
      return std::none_of(only.begin(), only.end(),
                          [&](const std::string& p) { return m.label.rfind(p, 0) == 0; });
    });
    if (methods.empty()) {
      std::fprintf(stderr, "stereoball-bench-detect: --only matches no method label\n");
      return 2;
    }
  }
  std::vector<Tally> tallies(methods.size());
  // Voting statistics of p2p (k=5) vs gradient voting on the ball scenes.
  std::map<std::string, std::vector<double>> voters, increments, ratio;
  EdgeFloor syn_floor, real_floor;

  for (const auto& size : sizes) {
    const auto suite = bd::make_suite(size, per_kind, seed);
    if (!dump_dir.empty()) {
      fs::create_directories(dump_dir);
      for (size_t i = 0; i < suite.size(); ++i)
        cv::imwrite((fs::path(dump_dir) / cv::format("%dx%d_%03zu_%s.png", size.width, size.height,
                                                     i, bd::scene_kind_name(suite[i].kind).c_str()))
                        .string(),
                    suite[i].image);
    }
    std::vector<cv::Mat> real_resized;
    for (const auto& r : real) {
      cv::Mat m;
      cv::resize(r, m, size, 0, 0, cv::INTER_AREA);
      real_resized.push_back(m);
    }
    for (size_t mi = 0; mi < methods.size(); ++mi) {
      auto det = methods[mi].make(size);
      Tally& t = tallies[mi];
      time_ms(*det, suite.front().image, nullptr);  // warm-up: first-call allocations
      for (const auto& scene : suite) {
        std::vector<bd::Circle> found;
        t.synth_ms[size.width].push_back(time_ms(*det, scene.image, &found));
        const auto m = bd::match_circles(found, scene.truth, min_iou);
        t.tp += m.true_positives;
        t.fp += m.false_positives;
        t.fn += m.false_negatives;
        auto& k = t.per_kind[bd::scene_kind_name(scene.kind)];
        k[0] += m.true_positives;
        k[1] += m.false_positives;
        k[2] += m.false_negatives;
        t.errors_px.insert(t.errors_px.end(), m.centre_errors_px.begin(), m.centre_errors_px.end());
        if (!explain.empty() && methods[mi].label.rfind(explain, 0) == 0 &&
            (m.false_positives > 0 || m.false_negatives > 0)) {
          const size_t index = static_cast<size_t>(&scene - suite.data());
          std::printf("%s %dx%d_%03zu_%s: fp %d fn %d |", methods[mi].label.c_str(), size.width,
                      size.height, index, bd::scene_kind_name(scene.kind).c_str(),
                      m.false_positives, m.false_negatives);
          for (const auto& c : scene.truth)
            std::printf(" truth(%.1f,%.1f,%.1f)", c.x_px, c.y_px, c.radius_px);
          for (const auto& c : found)
            std::printf(" found(%.1f,%.1f,%.1f,%.2f)", c.x_px, c.y_px, c.radius_px, c.score);
          std::printf("\n");
        }
        const auto* d = det->diagnostics();
        const bool voting = methods[mi].label == "p2p k=5" || methods[mi].label == "gradient";
        if (voting && d && !scene.truth.empty() && size.width == 640) {
          voters[methods[mi].label].push_back(static_cast<double>(d->voters));
          increments[methods[mi].label].push_back(static_cast<double>(d->increments));
          ratio[methods[mi].label].push_back(d->peak_to_mean);
        }
      }
      for (const auto& img : real_resized)
        t.real_ms[size.width].push_back(time_ms(*det, img, nullptr));
    }
    if (size.width == 640) {
      for (const auto& scene : suite) time_edge_step(scene.image, syn_floor);
      for (const auto& img : real_resized) time_edge_step(img, real_floor);
    }
  }

  std::printf(
      "Synthetic suite: %d scenes per kind x 10 kinds x 2 sizes, seed %u, IoU >= %.2f; "
      "real: %zu images from %s resized to each size; times = median thread CPU ms, 1 thread.\n\n",
      per_kind, seed, min_iou, real.size(), real_dir.c_str());
  std::printf("%-20s %6s %6s %6s %9s %10s %10s %10s %10s\n", "method", "P", "R", "F1", "err_px",
              "syn352ms", "syn640ms", "real352ms", "real640ms");
  for (size_t mi = 0; mi < methods.size(); ++mi) {
    const Tally& t = tallies[mi];
    const auto s = bd::detection_scores(t.tp, t.fp, t.fn);
    auto med = [](const std::map<int, std::vector<double>>& m, int w) {
      const auto it = m.find(w);
      return it == m.end() ? 0.0 : median(it->second);
    };
    std::printf("%-20s %6.3f %6.3f %6.3f %9.3f %10.2f %10.2f %10.2f %10.2f\n",
                methods[mi].label.c_str(), s.precision, s.recall, s.f1, median(t.errors_px),
                med(t.synth_ms, 352), med(t.synth_ms, 640), med(t.real_ms, 352),
                med(t.real_ms, 640));
  }
  print_speed_ratios(methods, tallies, syn_floor, real_floor);

  std::printf("\nF1 per scene kind (both sizes)\n%-20s", "method");
  const auto& kinds = tallies.front().per_kind;
  for (const auto& [kind, _] : kinds) std::printf(" %10s", kind.c_str());
  std::printf("\n");
  for (size_t mi = 0; mi < methods.size(); ++mi) {
    std::printf("%-20s", methods[mi].label.c_str());
    for (const auto& [kind, c] : tallies[mi].per_kind)
      std::printf(" %10.2f", bd::detection_scores(c[0], c[1], c[2]).f1);
    std::printf("\n");
  }

  std::printf(
      "\nVoting at 640x480, ball scenes (medians): edge points voting, accumulator "
      "increments, smoothed peak/mean\n");
  for (const auto& label : {std::string("p2p k=5"), std::string("gradient")})
    std::printf("%-18s voters %8.0f  increments %9.0f  peak/mean %8.1f\n", label.c_str(),
                median(voters[label]), median(increments[label]), median(ratio[label]));
  k_selection_table();
  stereoball::bench_detect::run_real_photo_table(families, std::get<0>(labelled), real_repeats,
                                                 min_iou, verbose_tuning, breakdown, time_cap,
                                                 detections);
  return 0;
}
