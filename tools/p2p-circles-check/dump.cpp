// Prints every circle the Pixel-to-Pixel detector finds, in hexadecimal floating point (bit for
// bit), for a fixed list of settings and entry points, on the labelled photographs, the real
// basketball frames halved to 1152x648 and a synthetic suite. Two builds' outputs are compared
// with diff (check.sh); not part of the CMake build.
#include "ball_detector/core/circle_labels.hpp"
#include "ball_detector/core/p2p_detector.hpp"
#include "ball_detector/core/synthetic.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

namespace bd = stereoball::ball_detector;
namespace fs = std::filesystem;

namespace {

std::string only_tag;     // argv[4]: run only this setting ("node" = the node's entry points)
std::string only_images;  // argv[5]: only images whose name starts with this

struct Image {
  std::string name;
  cv::Mat bgr;
  double rmin = 0.0;
};

void print(const std::string& tag, const std::vector<bd::Circle>& cs,
           const bd::DetectionDiagnostics* d = nullptr) {
  std::printf("%s n=%zu", tag.c_str(), cs.size());
  if (d)
    std::printf(" inc=%lld voters=%lld", static_cast<long long>(d->increments),
                static_cast<long long>(d->voters));
  std::printf("\n");
  for (const auto& c : cs) std::printf("  %a %a %a %a\n", c.x_px, c.y_px, c.radius_px, c.score);
}

bd::PixelToPixelParams base(cv::Size s, std::vector<int> ks, double rmin) {
  bd::PixelToPixelParams p;
  p.k_values = std::move(ks);
  const double side = std::min(s.width, s.height);
  p.min_radius_px = rmin > 0.0 ? rmin : 0.025 * side;
  p.max_radius_px = 0.2 * side;
  p.min_separation_px = 0.04 * side;
  p.max_circles = 100;
  return p;
}

void run_image(const Image& im) {
  const cv::Size s = im.bgr.size();
  std::vector<std::pair<std::string, bd::PixelToPixelParams>> settings;
  {  // multi-scale (small radii at full resolution), as bench detect once chose it; its current
     // choice is chosen_setting.cpp's
    auto p = base(s, {3, 5}, im.rmin);
    p.coarse_to_fine = true;
    p.fine_below_radius_px = 2.0 * p.min_radius_px;
    p.fine_k_values = {3};
    p.refine_params.band_per_radius = 0.035;
    p.min_score = 0.6;
    p.refine_params.clutter_ring_per_radius = 0.2;
    p.max_peaks_examined = 50;
    settings.push_back({"multi", p});
  }
  {
    auto p = base(s, {3, 5}, im.rmin);
    p.coarse_to_fine = true;
    p.min_score = 0.45;
    p.refine_params.clutter_ring_per_radius = 0.1;
    p.max_peaks_examined = 200;
    settings.push_back({"c2f", p});
    p.polish = false;
    p.min_score = 0.35;
    settings.push_back({"c2f-nopolish", p});
  }
  {
    auto p = base(s, {3, 5, 8}, im.rmin);
    p.min_score = 0.45;
    p.refine_params.band_per_radius = 0.035;
    p.refine_params.clutter_ring_per_radius = 0.1;
    p.max_peaks_examined = 200;
    settings.push_back({"full", p});
  }
  {
    auto p = base(s, {5, 8, 15}, im.rmin);
    p.isolate_arc = false;
    p.max_peaks_examined = 200;
    settings.push_back({"paper", p});
  }
  settings.push_back({"k5", base(s, {5}, 0.0)});
  for (const auto& [tag, p] : settings) {
    if (!only_tag.empty() && tag != only_tag) continue;
    bd::PixelToPixelDetector det(p);
    const auto cs = det.detect(im.bgr);
    print(im.name + " " + tag, cs, det.diagnostics());
  }
  if (!only_tag.empty() && only_tag != "node") return;
  // The node's entry points: thresholds of the image, hints with a margin, a camera, a
  // redetect of another band, seeds, and seeds without brightness.
  // The node's p2p settings (config/ball_detector.yaml), scaled to the width as the node does.
  const double f = std::max(1.0, s.width / 640.0);
  bd::PixelToPixelParams p;
  p.k_values = {static_cast<int>(std::lround(3 * f)), static_cast<int>(std::lround(5 * f))};
  p.min_radius_px = 4.0 * f;
  p.max_radius_px = 250.0 * f;
  p.min_separation_px = 10.0 * f;
  p.refine_params.clutter_ring_per_radius = 0.1;
  p.refine_params.clutter_min_radius_px = 30.0 * f;
  bd::PixelToPixelDetector det(p);
  det.set_camera(
      stereoball::stereo::PinholeCamera{1.1 * s.width, {0.5 * s.width, 0.45 * s.height}});
  bd::EdgeMap work;
  const bd::EdgeThresholds th = bd::measure_edge_thresholds(im.bgr, p.edge, work);
  bd::SearchHints lo;
  lo.radii = {p.min_radius_px, 60.0 * f};
  lo.centre_margin_px = 15;
  lo.min_inside_fraction = 0.3;
  const auto a = det.detect(im.bgr, th, lo);
  print(im.name + " node-lo", a, det.diagnostics());
  bd::SearchHints hi;
  hi.radii = {50.0 * f, p.max_radius_px};
  hi.centre_margin_px = 40;
  const auto b = det.redetect(hi);
  print(im.name + " node-redetect", b, det.diagnostics());
  bd::PixelToPixelDetector other(p);
  print(im.name + " node-redetect-from", other.redetect_from(det, lo), other.diagnostics());
  std::vector<bd::Circle> seeds;
  for (const auto& c : a) seeds.push_back({c.x_px + 1.5, c.y_px - 1.0, c.radius_px * 1.04, 0.0});
  for (const auto& c : b) seeds.push_back({c.x_px - 1.0, c.y_px + 2.0, c.radius_px * 0.97, 0.0});
  bd::SearchHints all;
  all.radii = {p.min_radius_px, p.max_radius_px};
  print(im.name + " node-seeds", det.detect_at_seeds(im.bgr, th, all, seeds));
  if (im.bgr.channels() == 3)
    print(im.name + " node-seeds-nobright",
          det.detect_at_seeds_without_brightness(im.bgr, all, seeds));
  // The split entry points.
  if (det.cast_votes(im.bgr)) {
    const int n = det.find_peaks_of_votes();
    std::vector<bd::PeakCircles> per;
    for (int i = n - 1; i >= 0; --i) per.insert(per.begin(), det.refine_peak(i));
    print(im.name + " split", det.select_circles(per), det.diagnostics());
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr,
                 "usage: dump PROJECT_ROOT SHARED_DATA [max-images [setting [image-prefix]]]\n");
    return 2;
  }
  const fs::path root = argv[1], shared = argv[2];
  std::vector<Image> images;
  std::vector<fs::path> label_files;
  for (const auto& e : fs::directory_iterator(root / "tests/data/circles"))
    if (e.path().extension() == ".circles") label_files.push_back(e.path());
  std::sort(label_files.begin(), label_files.end());
  for (const auto& f : label_files) {
    std::ifstream in(f);
    std::stringstream ss;
    ss << in.rdbuf();
    const auto parsed = bd::parse_circle_labels(ss.str(), f.string());
    if (const auto* err = std::get_if<std::string>(&parsed)) {
      std::fprintf(stderr, "%s\n", err->c_str());
      return 1;
    }
    const auto& labels = std::get<bd::CircleLabels>(parsed);
    const cv::Mat img = cv::imread((root / labels.image_path).string(), cv::IMREAD_UNCHANGED);
    if (img.empty()) continue;
    cv::Mat bgr = img;
    if (img.channels() == 4) cv::cvtColor(img, bgr, cv::COLOR_BGRA2BGR);
    images.push_back({f.stem().string(), bgr, labels.min_radius_px.value_or(0.0)});
  }
  // Every third frame of each eye, halved as the node's 1152x648 searches see them.
  for (const char* eye : {"left", "right"}) {
    std::vector<fs::path> frames;
    for (const auto& e : fs::directory_iterator(shared / "real-stereo-basketball" / eye))
      if (e.path().extension() == ".jpg") frames.push_back(e.path());
    std::sort(frames.begin(), frames.end());
    for (std::size_t i = 0; i < frames.size(); i += 3) {
      const cv::Mat img = cv::imread(frames[i].string());
      if (img.empty()) continue;
      cv::Mat half;
      cv::resize(img, half, cv::Size(img.cols / 2, img.rows / 2), 0, 0, cv::INTER_AREA);
      images.push_back({frames[i].stem().string(), half, 0.0});
    }
  }
  const auto suite = bd::make_suite(cv::Size(640, 480), 2, 11);
  for (std::size_t i = 0; i < suite.size(); ++i)
    images.push_back({"synth_" + std::to_string(i), suite[i].image, 0.0});
  // Grey versions of a few, for the grey edge path.
  const std::size_t n = images.size();
  for (std::size_t i = 0; i < n; i += 7) {
    if (images[i].bgr.channels() != 3) continue;
    cv::Mat g;
    cv::cvtColor(images[i].bgr, g, cv::COLOR_BGR2GRAY);
    images.push_back({images[i].name + "_grey", g, images[i].rmin});
  }
  const std::size_t limit = argc > 3 ? std::stoul(argv[3]) : images.size();
  if (argc > 4) only_tag = argv[4];
  if (argc > 5) only_images = argv[5];
  for (std::size_t i = 0; i < std::min(limit, images.size()); ++i)
    if (images[i].name.rfind(only_images, 0) == 0) run_image(images[i]);
  return 0;
}
