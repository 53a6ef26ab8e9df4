// Runs Pixel-to-Pixel at the setting `bench detect` chose on the photographs ("scale
// fine<2.00xrmin fine-stop=3 k=3,5 fine k=3 give-up coarse-peaks=50 score>=0.55 clutter=0.2
// peaks=50", as tools/bench-detect/main.cpp builds it) on every labelled photograph of
// tests/data/circles: its circles bit for bit, and the thread CPU time of the detect() calls.
// For profiling the photographs' cost (callgrind) and comparing two builds' circles and times;
// built by hand like dump.cpp (README), not part of the CMake build.
#include "ball_detector/core/circle_labels.hpp"
#include "ball_detector/core/p2p_detector.hpp"

#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>

#include <time.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

namespace bd = stereoball::ball_detector;
namespace fs = std::filesystem;

namespace {

struct Photo {
  std::string name;
  cv::Mat bgr;
  double min_radius_px = 0.0;
};

// bench detect's multi_scale_params(s, rmin, {3, 5}, 2.0, 0.55, 0.2, 50) with its "scale"
// family's additions (fine_give_up, coarse_max_peaks_examined 50, fine_stop_after_missed_peaks 3).
bd::PixelToPixelParams chosen_setting(cv::Size s, double min_radius_px) {
  bd::PixelToPixelParams p;
  const double side = std::min(s.width, s.height);
  p.k_values = {3, 5};
  p.min_radius_px = min_radius_px;
  p.max_radius_px = 0.2 * side;
  p.min_separation_px = 0.04 * side;
  p.coarse_to_fine = true;
  p.fine_below_radius_px = 2.0 * min_radius_px;
  p.fine_k_values = {3};
  p.refine_params.band_per_radius = 0.035;
  p.min_score = 0.55;
  p.refine_params.clutter_ring_per_radius = 0.2;
  p.max_circles = 100;
  p.max_peaks_examined = 50;
  p.fine_give_up = true;
  p.coarse_max_peaks_examined = 50;
  p.fine_stop_after_missed_peaks = 3;
  return p;
}

// The labelled photographs, in file name order, with their labels' smallest radius (bench
// detect's default where a label file has none).
std::vector<Photo> photos(const fs::path& root, const std::string& only) {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(root / "tests/data/circles"))
    if (e.path().extension() == ".circles") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  std::vector<Photo> out;
  for (const auto& f : files) {
    if (!only.empty() && f.stem().string() != only) continue;
    std::ifstream in(f);
    std::stringstream text;
    text << in.rdbuf();
    const auto parsed = bd::parse_circle_labels(text.str(), f.string());
    const auto* labels = std::get_if<bd::CircleLabels>(&parsed);
    if (!labels) continue;
    const cv::Mat image = cv::imread((root / labels->image_path).string(), cv::IMREAD_COLOR);
    if (image.empty()) continue;
    const double rmin = labels->min_radius_px.value_or(0.025 * std::min(image.cols, image.rows));
    out.push_back({f.stem().string(), image, rmin});
  }
  return out;
}

double thread_cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return 1e3 * static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_nsec);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: chosen_setting PROJECT_ROOT [repeats [photo|- [all|small|large]]]\n"
                 "  small / large: only the full-resolution search of the small radii, or only\n"
                 "  the coarse-to-fine search of the others\n");
    return 2;
  }
  cv::setNumThreads(1);  // as bench detect times it
  const int repeats = argc > 2 ? std::max(1, std::atoi(argv[2])) : 1;
  const std::string only = argc > 3 && std::string(argv[3]) != "-" ? argv[3] : "";
  const std::string part = argc > 4 ? argv[4] : "all";
  const std::vector<Photo> all = photos(argv[1], only);
  double total_ms = 0.0;
  for (int r = 0; r < repeats; ++r)
    for (const Photo& photo : all) {
      bd::PixelToPixelParams p = chosen_setting(photo.bgr.size(), photo.min_radius_px);
      if (part == "small") p = p.small_circle_search();
      if (part == "large") p = p.large_circle_search();
      bd::PixelToPixelDetector detector(p);
      const double start = thread_cpu_ms();
      const auto circles = detector.detect(photo.bgr);
      total_ms += thread_cpu_ms() - start;
      if (r > 0) continue;
      std::printf("%s %dx%d n=%zu\n", photo.name.c_str(), photo.bgr.cols, photo.bgr.rows,
                  circles.size());
      for (const auto& c : circles)
        std::printf("  %a %a %a %a\n", c.x_px, c.y_px, c.radius_px, c.score);
    }
  std::fprintf(stderr, "photos %zu, repeats %d, detect thread CPU %.1f ms\n", all.size(), repeats,
               total_ms);
  return 0;
}
