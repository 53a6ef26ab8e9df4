// stereoball-bench-jpeg-accuracy: what JPEG compression of the stereo stream costs the
// detector. Renders frames with the simulator core, runs the ball detector pipeline on the raw
// frames and on JPEG-encoded-then-decoded copies at each quality, and prints centre and 3D
// differences (JPEG vs raw, and both vs ground truth), detection rates and bytes per frame.
// Prints figures only; nothing is asserted.

#include "common/util/cli11.hpp"

#include <opencv2/imgcodecs.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "ball_detector/core/p2p_detector.hpp"
#include "ball_detector/pipeline/detector_params_file.hpp"
#include "ball_detector/pipeline/stereo_pipeline.hpp"
#include "common/node/common_flags.hpp"
#include "simulator/core/simulator.hpp"
#include "simulator/io/scenario_file.hpp"
#include "simulator/io/sim_params_file.hpp"
#include "stereo/frame/frame_codec.hpp"
#include "two_host_system.hpp"

namespace sb = stereoball;
namespace bd = stereoball::ball_detector;

namespace {

// Figures of one variant (raw or one JPEG quality) over all frames.
struct Stats {
  int frames = 0, found = 0, found_both = 0;  // found_both: this variant and raw both found
  std::vector<double> centre_vs_raw_px, position_vs_raw_mm, centre_vs_truth_px,
      position_vs_truth_mm;
  double bytes = 0, encode_ms = 0, decode_ms = 0;
};

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// One JPEG variant: quality and colour resolution (jpeg_chroma), named "jpeg90" for 4:4:4 and
// "jpeg90/420" otherwise.
struct Variant {
  int quality = 90;
  std::string chroma = "444";
  std::string name() const {
    return "jpeg" + std::to_string(quality) + (chroma == "444" ? "" : "/" + chroma);
  }
  sb::stereo::FrameCodecParams codec() const {
    sb::stereo::FrameCodecParams p;
    p.frame_encoding = "jpeg";
    p.jpeg_quality = quality;
    p.jpeg_chroma = chroma;
    return p;
  }
};

std::vector<Variant> variants_of(const std::vector<int>& qualities,
                                 const std::vector<std::string>& chromas) {
  std::vector<Variant> out;
  for (const auto& c : chromas)
    for (int q : qualities) out.push_back({q, c});
  return out;
}

double dist3(const cv::Vec3d& a, const cv::Vec3d& b) {
  return cv::norm(a - b);
}

void compare_to_truth(const bd::StereoDetection& d, const sb::simulator::GroundTruth& g, Stats& s) {
  if (d.status != bd::DetectionStatus::kFound || !g.ball_visible_left || !g.ball_visible_right) {
    return;
  }
  s.centre_vs_truth_px.push_back(
      std::hypot(d.left.x_px - g.ball_left_px.x, d.left.y_px - g.ball_left_px.y));
  const cv::Vec3d truth(g.ball_camera_m.x, g.ball_camera_m.y, g.ball_camera_m.z);
  s.position_vs_truth_mm.push_back(1e3 * dist3(d.position_m, truth));
}

void print_row(const std::string& name, const Stats& s) {
  namespace sd = sb::distributed;
  const double n = std::max(1, s.frames);
  std::printf("%-11s %7.0f %6.1f%% | %7.3f %7.3f %7.3f | %7.1f %7.1f | %7.3f %7.1f | %6.2f %6.2f\n",
              name.c_str(), s.bytes / n / 1024.0, 100.0 * s.found / n,
              sd::percentile(s.centre_vs_raw_px, 50), sd::percentile(s.centre_vs_raw_px, 99),
              s.centre_vs_raw_px.empty()
                  ? 0.0
                  : *std::max_element(s.centre_vs_raw_px.begin(), s.centre_vs_raw_px.end()),
              sd::percentile(s.position_vs_raw_mm, 50), sd::percentile(s.position_vs_raw_mm, 99),
              sd::percentile(s.centre_vs_truth_px, 50), sd::percentile(s.position_vs_truth_mm, 50),
              s.encode_ms / n, s.decode_ms / n);
}

// Single-eye mode on real images (no ground truth): the best raw circle vs the nearest circle
// found on the JPEG copy, per quality.
int run_images(const std::vector<std::string>& images, const std::vector<Variant>& variants,
               const bd::BallDetectorParams& params) {
  namespace sd = sb::distributed;
  std::printf("single eye (P2P) on %zu real images; shift of the best raw circle\n", images.size());
  std::printf("variant     KiB/img  matched | centre shift px p50 / max | radius shift px max\n");
  for (const Variant& v : variants) {
    std::vector<double> shift, radius;
    double bytes = 0;
    int matched = 0, total = 0;
    for (const auto& path : images) {
      const cv::Mat raw = cv::imread(path, cv::IMREAD_COLOR);
      if (raw.empty()) {
        std::fprintf(stderr, "stereoball-bench-jpeg-accuracy: cannot read image %s\n",
                     path.c_str());
        return 2;
      }
      sb::stereo::EyeEncoder encoder(v.codec());
      if (auto st = encoder.encode(raw); !st) {
        std::fprintf(stderr, "stereoball-bench-jpeg-accuracy: %s: %s\n", path.c_str(),
                     st.error().c_str());
        return 2;
      }
      const std::vector<uint8_t>& buffer = encoder.bytes();
      bytes += static_cast<double>(buffer.size());
      bd::PixelToPixelDetector a(params.detector_params()), b(params.detector_params());
      const auto r = a.detect(raw);
      const auto j = b.detect(cv::imdecode(buffer, cv::IMREAD_COLOR));
      if (r.empty()) continue;
      ++total;
      double best = 1e9, dr = 0;
      for (const auto& c : j) {
        const double d = std::hypot(c.x_px - r[0].x_px, c.y_px - r[0].y_px);
        if (d < best) {
          best = d;
          dr = std::abs(c.radius_px - r[0].radius_px);
        }
      }
      if (best <= std::max(3.0, 0.25 * r[0].radius_px)) {  // same circle found again
        ++matched;
        shift.push_back(best);
        radius.push_back(dr);
      }
    }
    std::printf("%-11s %7.0f  %3d/%-3d | %8.3f / %8.3f      | %8.3f\n", v.name().c_str(),
                bytes / std::max<size_t>(1, images.size()) / 1024, matched, total,
                sd::percentile(shift, 50), sd::percentile(shift, 100), sd::percentile(radius, 100));
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "stereoball-bench-jpeg-accuracy: detection accuracy of JPEG-compressed stereo frames vs\n"
      "raw, on simulator renderings (prints figures only)"};
  std::vector<std::string> scenarios{"ball_rolling_away", "ball_rolling_across", "ball_still"};
  std::vector<int> qualities{95, 90, 85, 75, 50};
  int frames_per_scenario = 40;
  double spacing_s = 0.25;
  std::string detector_config = sb::node::default_config_path("ball_detector.yaml");
  std::string sim_config = sb::node::default_config_path("simulator.yaml");
  std::string scenarios_dir = sb::node::default_config_path("scenarios");
  app.add_option("--scenarios", scenarios, "scenario names")->capture_default_str();
  app.add_option("--quality", qualities, "JPEG qualities to try")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  std::vector<std::string> chromas{"444"};
  app.add_option("--chroma", chromas, "jpeg_chroma values to try, each at every quality")
      ->check(CLI::IsMember(sb::stereo::jpeg_chroma_choices()))
      ->capture_default_str();
  app.add_option("--frames", frames_per_scenario, "frames per scenario")
      ->check(CLI::Range(1, 10000))
      ->capture_default_str();
  app.add_option("--spacing", spacing_s, "simulated seconds between frames")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--detector-config", detector_config, "ball_detector parameters")
      ->capture_default_str();
  app.add_option("--sim-config", sim_config, "simulator parameters")->capture_default_str();
  std::vector<std::string> images;
  app.add_option("--images", images, "real images: single-eye raw vs JPEG comparison instead")
      ->check(CLI::ExistingFile);
  bool verbose = false;
  app.add_flag("--verbose", verbose, "print the raw detection status of every frame");
  CLI11_PARSE(app, argc, argv);

  auto detector_params = bd::load_detector_params(detector_config);
  if (!detector_params) {
    std::fprintf(stderr, "stereoball-bench-jpeg-accuracy: %s\n", detector_params.error().c_str());
    return 2;
  }
  const std::vector<Variant> variants = variants_of(qualities, chromas);
  if (!images.empty()) return run_images(images, variants, *detector_params);
  auto sim_params = sb::simulator::load_sim_params(sim_config);
  if (!sim_params) {
    std::fprintf(stderr, "stereoball-bench-jpeg-accuracy: %s\n", sim_params.error().c_str());
    return 2;
  }
  Stats raw;
  std::map<std::string, Stats> jpeg;
  for (const auto& name : scenarios) {
    auto scenario = sb::simulator::load_scenario_by_name(name, scenarios_dir);
    if (!scenario) {
      std::fprintf(stderr, "stereoball-bench-jpeg-accuracy: %s\n", scenario.error().c_str());
      return 2;
    }
    sb::simulator::Simulator sim(*sim_params, *scenario);
    bd::StereoPipeline raw_pipeline(*detector_params);
    std::map<std::string, std::unique_ptr<bd::StereoPipeline>> pipelines;
    for (const Variant& v : variants) {
      pipelines[v.name()] = std::make_unique<bd::StereoPipeline>(*detector_params);
      pipelines[v.name()]->set_calibration(sim.calibration());
    }
    if (auto e = raw_pipeline.set_calibration(sim.calibration()); !e) {
      std::fprintf(stderr, "stereoball-bench-jpeg-accuracy: calibration: %s\n", e.error().c_str());
      return 2;
    }
    for (int i = 0; i < frames_per_scenario; ++i) {
      const auto t_ns = static_cast<int64_t>((0.5 + spacing_s * i) * 1e9);
      const auto frame = sim.step(std::nullopt, t_ns);
      const bd::StereoDetection r = raw_pipeline.step(frame.left, frame.right, false);
      ++raw.frames;
      raw.bytes += static_cast<double>(frame.left.total() * 3 * 2);
      if (r.status == bd::DetectionStatus::kFound) ++raw.found;
      if (verbose) {
        std::printf("%s t=%.2fs raw: %s %s (truth visible %d/%d)\n", name.c_str(), t_ns / 1e9,
                    bd::to_string(r.status), r.reason.c_str(), frame.truth.ball_visible_left,
                    frame.truth.ball_visible_right);
      }
      compare_to_truth(r, frame.truth, raw);
      for (const Variant& v : variants) {
        Stats& s = jpeg[v.name()];
        cv::Mat eyes[2];
        const cv::Mat* in[2] = {&frame.left, &frame.right};
        for (int e = 0; e < 2; ++e) {
          auto t0 = std::chrono::steady_clock::now();
          // The publishers' own encoder (camera_server, simulator with frame_encoding jpeg).
          sb::stereo::EyeEncoder encoder(v.codec());
          if (auto st = encoder.encode(*in[e]); !st) {
            std::fprintf(stderr, "stereoball-bench-jpeg-accuracy: %s\n", st.error().c_str());
            return 1;
          }
          s.encode_ms += ms_since(t0);
          s.bytes += static_cast<double>(encoder.bytes().size());
          t0 = std::chrono::steady_clock::now();
          eyes[e] = cv::imdecode(encoder.bytes(), cv::IMREAD_COLOR);
          s.decode_ms += ms_since(t0);
        }
        const bd::StereoDetection d = pipelines[v.name()]->step(eyes[0], eyes[1], false);
        if (verbose) {
          std::printf("  %s: %s %s\n", v.name().c_str(), bd::to_string(d.status), d.reason.c_str());
        }
        ++s.frames;
        if (d.status == bd::DetectionStatus::kFound) ++s.found;
        compare_to_truth(d, frame.truth, s);
        if (d.status == bd::DetectionStatus::kFound && r.status == bd::DetectionStatus::kFound) {
          ++s.found_both;
          s.centre_vs_raw_px.push_back(
              std::max(std::hypot(d.left.x_px - r.left.x_px, d.left.y_px - r.left.y_px),
                       std::hypot(d.right.x_px - r.right.x_px, d.right.y_px - r.right.y_px)));
          s.position_vs_raw_mm.push_back(1e3 * dist3(d.position_m, r.position_m));
        }
      }
    }
  }
  std::printf("%d frames (%zu scenarios x %d, every %.2f s of simulated time), %dx%d\n", raw.frames,
              scenarios.size(), frames_per_scenario, spacing_s, sim_params->width_px,
              sim_params->height_px);
  std::printf(
      "variant     KiB/pair  found | centre diff vs raw (px) | 3D vs raw (mm)  | vs truth p50    | "
      "enc/dec ms per pair\n"
      "                            |    p50     p99     max  |    p50     p99  |   px      mm    "
      "|\n");
  print_row("raw", raw);
  for (const Variant& v : variants) print_row(v.name(), jpeg[v.name()]);
  std::printf(
      "centre diff = larger of the left and right eye centre shifts, frames where both "
      "raw and JPEG found the ball\n");
  return 0;
}
