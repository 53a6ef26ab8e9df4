// stereoball detect: find circles in image files with any detector of ball_detector/core.

#include "ball_detector/core/circle.hpp"

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include "common/util/cli11.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "ball_detector/core/p2p_detector.hpp"
#include "ball_detector/pipeline/detector_params_file.hpp"
#include "ball_detector/pipeline/stereo_pipeline.hpp"
#include "common/util/install_layout.hpp"
#include "stereo/image/image_file.hpp"

namespace bd = stereoball::ball_detector;
namespace sb = stereoball;
namespace fs = std::filesystem;

namespace {

// Writes edge map, accumulator heat map and overlay; returns an error message or "".
std::string write_debug(const fs::path& dir, const std::string& image_path, const cv::Mat& image,
                        const bd::CircleDetector& detector, const std::vector<bd::Circle>& found) {
  const std::string stem = fs::path(image_path).stem().string();
  cv::Mat overlay;
  if (image.channels() == 1)
    cv::cvtColor(image, overlay, cv::COLOR_GRAY2BGR);
  else if (image.channels() == 4)
    cv::cvtColor(image, overlay, cv::COLOR_BGRA2BGR);
  else
    overlay = image.clone();
  for (size_t i = 0; i < found.size(); ++i) {
    const auto& c = found[i];
    const cv::Scalar colour = i == 0 ? cv::Scalar(0, 255, 0) : cv::Scalar(0, 200, 255);
    // Shift 4: sub-pixel drawing, so the overlay shows the refined centre.
    cv::circle(overlay, cv::Point(cvRound(c.x_px * 16), cvRound(c.y_px * 16)),
               cvRound(c.radius_px * 16), colour, 1, cv::LINE_AA, 4);
    cv::drawMarker(overlay, cv::Point(cvRound(c.x_px), cvRound(c.y_px)), colour, cv::MARKER_CROSS,
                   7);
    cv::putText(overlay, cv::format("%.2f", c.score),
                cv::Point(cvRound(c.x_px + c.radius_px), cvRound(c.y_px)), cv::FONT_HERSHEY_SIMPLEX,
                0.4, colour);
  }
  std::vector<std::pair<std::string, cv::Mat>> out = {{stem + "_overlay.png", overlay}};
  if (const auto* diag = detector.diagnostics()) {
    if (!diag->edges.empty()) out.push_back({stem + "_edges.png", diag->edges});
    if (!diag->accumulator.empty()) {
      cv::Mat norm, heat;
      cv::normalize(diag->accumulator, norm, 0, 255, cv::NORM_MINMAX, CV_8U);
      cv::applyColorMap(norm, heat, cv::COLORMAP_JET);
      out.push_back({stem + "_accumulator.png", heat});
    }
  }
  for (const auto& [name, mat] : out) {
    const fs::path p = dir / name;
    bool ok = false;
    try {
      ok = cv::imwrite(p.string(), mat);
    } catch (const cv::Exception&) {
      ok = false;
    }
    if (!ok) return "cannot write '" + p.string() + "'";
  }
  return "";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Find circles (balls) in images. Prints x y r score per circle, best first; coordinates "
      "are pixels with pixel centres on integers."};
  std::string method = "p2p";
  bd::DetectorOptions opt;
  std::vector<int> ks;
  bool json = false;
  std::string debug_dir;
  int threads = 1;
  // Larger images are refused from their header, before decoding: a small file can claim
  // 20000x20000 (1.2 GB of pixels). 4096x4096 leaves room above any camera StereoBall runs.
  int max_width_px = 4096, max_height_px = 4096;
  std::vector<std::string> images;
  app.add_option("--method", method, "Detector: p2p, cht, gradient, opencv, opencv-alt, edcircles")
      ->capture_default_str()
      ->check(CLI::IsMember(bd::detector_names()));
  app.add_option("--k", ks,
                 "Pixel-to-Pixel half window size k (window 2k+1); several = multi-k, as "
                 "--k 3,5,8 or --k 3 --k 5 --k 8. Default 5")
      ->allow_extra_args(false)
      ->delimiter(',')
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
      ->check(CLI::Range(1, 31));
  app.add_flag("--coarse", opt.coarse_to_fine,
               "p2p: find candidates on the image halved, refine and score them at full "
               "resolution (faster on photographs)");
  app.add_option("--max", opt.max_circles, "Most circles reported per image")
      ->capture_default_str()
      ->check(CLI::Range(1, 100));
  app.add_option("--min-score", opt.min_score, "Drop circles scoring below this, [0, 1]")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--min-radius", opt.min_radius_px, "Smallest radius searched, pixels")
      ->capture_default_str();
  app.add_option("--max-radius", opt.max_radius_px, "Largest radius searched, pixels")
      ->capture_default_str();
  app.add_option("--min-separation", opt.min_separation_px,
                 "Closest two reported centres may be, pixels")
      ->capture_default_str();
  app.add_option("--opencv-param2", opt.opencv_param2,
                 "param2 of OpenCV HoughCircles (opencv: votes, opencv-alt: (0,1]); <0 = default");
  app.add_flag("--json", json,
               "One JSON object per image: {\"image\", \"ms\", \"circles\": [{x, y, r, score}]}");
  app.add_option("--debug-dir", debug_dir,
                 "Write <image>_edges.png, <image>_accumulator.png and <image>_overlay.png here");
  app.add_option("--threads", threads, "OpenCV worker threads (1 = one core, as on the robot)")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  app.add_option("--max-width", max_width_px, "Refuse wider images (from the header), pixels")
      ->capture_default_str()
      ->check(CLI::Range(1, 65535));
  app.add_option("--max-height", max_height_px, "Refuse taller images (from the header), pixels")
      ->capture_default_str()
      ->check(CLI::Range(1, 65535));
  std::string config_path = sb::paths::shipped_config_path("ball_detector.yaml");
  bool core_defaults = false;
  app.add_option("--config", config_path,
                 "p2p: the ball detector's parameters file whose detector settings (p2p:, "
                 "max_candidates_per_eye, input) are used, as the node uses them; the flags above "
                 "override them")
      ->capture_default_str();
  app.add_flag("--core-defaults", core_defaults,
               "p2p: the detector core's own defaults (k 5, grey edges, ...) instead of the "
               "node's settings");
  app.add_option("IMAGE", images, "Image files (png, jpg, ...)")->required();
  CLI11_PARSE(app, argc, argv);

  cv::setNumThreads(threads);
  // Our own one-line errors replace OpenCV's warnings about unreadable files.
  cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
  if (!ks.empty()) opt.k_values = ks;
  std::string error;
  std::unique_ptr<bd::CircleDetector> detector;
  // What a user trying a photo should see is what the robot sees: p2p takes the node's settings.
  std::optional<bd::DetectorInput> input;
  if (method == "p2p" && !core_defaults) {
    auto node = bd::load_detector_params(config_path);
    if (!node) {
      std::cerr << "stereoball-detect: " << node.error() << "\n";
      return 2;
    }
    bd::PixelToPixelParams p = node->detector_params();
    if (!ks.empty()) p.k_values = ks;
    if (app.count("--coarse") > 0) p.coarse_to_fine = opt.coarse_to_fine;
    if (app.count("--max") > 0) p.max_circles = opt.max_circles;
    if (app.count("--min-score") > 0) p.min_score = opt.min_score;
    if (app.count("--min-radius") > 0) p.min_radius_px = opt.min_radius_px;
    if (app.count("--max-radius") > 0) p.max_radius_px = opt.max_radius_px;
    if (app.count("--min-separation") > 0) p.min_separation_px = opt.min_separation_px;
    if (auto e = p.validate(); !e) {
      std::cerr << "stereoball-detect: p2p: " << e.error() << "\n";
      return 2;
    }
    input = node->input;
    detector = std::make_unique<bd::PixelToPixelDetector>(p);
  } else {
    detector = bd::make_detector(method, opt, &error);
  }
  if (!detector) {
    std::cerr << "stereoball-detect: " << error << "\n";
    return 2;
  }
  if (!debug_dir.empty()) {
    std::error_code ec;
    fs::create_directories(debug_dir, ec);
    if (ec || !fs::is_directory(debug_dir)) {
      std::cerr << "stereoball-detect: cannot create debug directory '" << debug_dir << "'\n";
      return 2;
    }
  }
  int failures = 0;
  for (const auto& path : images) {
    auto read = sb::stereo::read_image_file(path, {max_width_px, max_height_px});
    if (!read) {
      std::cerr << "stereoball-detect: " << read.error() << "\n";
      ++failures;
      continue;
    }
    const cv::Mat image = std::move(*read);
    if (const auto bad = bd::validate_image(image); !bad) {
      std::cerr << "stereoball-detect: '" << path << "': " << bad.error() << "\n";
      ++failures;
      continue;
    }
    const auto t0 = std::chrono::steady_clock::now();
    cv::Mat scratch;
    const auto circles =
        detector->detect(input ? bd::detector_input_image(image, *input, scratch) : image);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (json) {
      nlohmann::json j;
      j["image"] = path;
      j["ms"] = ms;
      j["circles"] = nlohmann::json::array();
      for (const auto& c : circles)
        j["circles"].push_back(
            {{"x", c.x_px}, {"y", c.y_px}, {"r", c.radius_px}, {"score", c.score}});
      std::cout << j.dump() << "\n";
    } else {
      std::printf("%s: %zu circle(s), %.2f ms\n", path.c_str(), circles.size(), ms);
      for (const auto& c : circles)
        std::printf("  x=%.2f y=%.2f r=%.2f score=%.3f\n", c.x_px, c.y_px, c.radius_px, c.score);
    }
    if (!debug_dir.empty()) {
      const std::string err = write_debug(debug_dir, path, image, *detector, circles);
      if (!err.empty()) {
        std::cerr << "stereoball-detect: " << err << "\n";
        ++failures;
      }
    }
  }
  return failures == 0 ? 0 : 1;
}
