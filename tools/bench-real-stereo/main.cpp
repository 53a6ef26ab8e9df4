// stereoball bench real-stereo: plays a real stereo set (left/, right/, truth CSV, calibration)
// through camera_server and ball_detector over DDS, as a user runs them, and scores every pair
// against the truth (README.md). Figures only: exit 0 when it ran, 1 on run errors, 2 on bad
// input.

#include "common/util/cli11.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <iostream>

#include "common/util/install_layout.hpp"
#include "real_stereo_report.hpp"
#include "real_stereo_run.hpp"
#include "real_stereo_set.hpp"
#include "stereo/frame/frame_codec.hpp"

namespace {

using namespace stereoball;
using namespace stereoball::real_stereo;

std::atomic<bool> g_stop{false};

void on_signal(int) {
  g_stop = true;
}

int bad_input(const std::string& what) {
  std::cerr << "stereoball-bench-real-stereo: " << what << "\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Real stereo pairs with a person's ground truth through camera_server (file source) and "
      "ball_detector over DDS, as a user runs them; every pair scored correct / wrong / missed "
      "(overall, per |dy| band), misses by the detector's reason, detector ms per frame. "
      "Figures only: exit 0 when it ran, 1 on run errors, 2 on bad input.",
      "stereoball-bench-real-stereo"};
  // The shared development set beside a source tree (build-tree programs only): no source path
  // is compiled in, an installed bench needs --set.
  std::string set_dir;
  if (const auto source = paths::default_roots().source_dir)
    set_dir = (*source / ".." / "shared" / "data" / "real-stereo-basketball").lexically_normal();
  std::string truth, calibration;
  std::string detector_base = paths::shipped_config_path("ball_detector.yaml");
  DetectorOverrides overrides;
  double diameter = 0;
  std::string image_limit;
  RunOptions options;
  options.bin_dir = paths::executable_dir().string();
  std::vector<std::string> only_pairs;
  bool in_process = false, verbose = false, json = false, no_retry = false;
  app.add_option("--set", set_dir,
                 "the real stereo set's folder (README.md: the set folder); default in a build "
                 "tree: ../shared/data/real-stereo-basketball beside the source tree")
      ->capture_default_str();
  app.add_option("--truth", truth, "truth CSV (default: SET/ball_truth.csv)");
  app.add_option("--calibration", calibration,
                 "rig calibration YAML (default: the one *.yaml in SET/calibration/)");
  app.add_option("--detector-base", detector_base,
                 "the detector configuration the overrides apply to (the shipped one)")
      ->capture_default_str();
  app.add_option("--detector-config", overrides.config_file,
                 "YAML whose keys are merged over the detector base (any subset of "
                 "config/ball_detector.yaml)");
  app.add_option("--ball-diameter-m", diameter, "ball.diameter_m (a size-7 basketball: 0.24)")
      ->check(CLI::Range(0.001, 5.0));
  app.add_flag("--no-floor-check", overrides.no_floor_check,
               "floor.tolerance_m: 0 (a ball in the hands or the air)");
  app.add_option("--image-limit", image_limit,
                 "detector image_limit WxH; the shipped 1920x1080 refuses 2304x1296 frames");
  double snapshot_skew_ms = -1;
  app.add_option("--snapshot-skew-ms", snapshot_skew_ms,
                 "epipolar.skew_ns for stills of free-running cameras whose files carry no "
                 "capture stamps (the documented snapshot allowance: 16.7, half a 30 Hz frame)")
      ->check(CLI::Range(0.0, 1000.0));
  app.add_option("--width-px", options.width_px,
                 "camera_server publish_width_px: frames (and calibration) scaled to this width; "
                 "the truth is scaled by the same factor (0 = native)")
      ->check(CLI::Range(0, 16384));
  app.add_option("--frame-encoding", options.frame_encoding,
                 "camera_server frame_encoding (jpeg crosses loopback DDS at any size)")
      ->check(CLI::IsMember({"raw", "jpeg", "png"}))
      ->capture_default_str();
  app.add_option("--jpeg-quality", options.jpeg_quality, "camera_server jpeg_quality")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  app.add_option("--jpeg-chroma", options.jpeg_chroma,
                 "camera_server jpeg_chroma: colour resolution of the JPEG eyes")
      ->check(CLI::IsMember(stereo::jpeg_chroma_choices()))
      ->capture_default_str();
  app.add_option("--rate-hz", options.rate_hz,
                 "camera_server playback rate; low enough for the detector to answer every "
                 "frame (a retry plays at half of it)")
      ->check(CLI::Range(0.05, 30.0))
      ->capture_default_str();
  app.add_option("--domain", options.domain, "private DDS domain of the run")
      ->check(CLI::Range(0, 232))
      ->capture_default_str();
  app.add_option("--partition", options.partition,
                 "DDS partition (default: bench-real-stereo-PID)");
  app.add_option("--bin-dir", options.bin_dir, "folder of camera_server and ball_detector")
      ->capture_default_str();
  app.add_option("--pair-timeout-s", options.pair_timeout_s,
                 "longest wait for the last answers after the last frame, s")
      ->check(CLI::Range(1.0, 600.0))
      ->capture_default_str();
  app.add_option("--warmup-s", options.warmup_s,
                 "the first pair is played this long before the set, answers unused: the "
                 "detector's first frames of a calibration are slow")
      ->check(CLI::Range(0.0, 120.0))
      ->capture_default_str();
  app.add_option("--pairs", only_pairs,
                 "play only these pair ids of the truth (comma separated), e.g. 2,4,9")
      ->delimiter(',');
  app.add_flag("--no-retry", no_retry, "do not play pairs without a detection again");
  app.add_flag("--in-process", in_process,
               "run the detector's pipeline library in this process (fast tuning; NOT the DDS "
               "path the figures of record use)");
  app.add_option("--reference", options.reference,
                 "with --in-process: this circle detector (edcircles, opencv-alt, ...) also runs "
                 "on every decoded left eye, rectified, alone; its CPU time per frame (plus the "
                 "decode) and how often the ball is among its circles are reported beside the "
                 "pipeline's: what one eye costs with another method, measured side by side");
  app.add_flag("--verbose,-v", verbose, "one line per pair");
  app.add_flag("--json", json, "JSON instead of the table");
  CLI11_PARSE(app, argc, argv);
  options.retry = !no_retry;
  if (!options.reference.empty()) {
    if (!in_process) return bad_input("--reference needs --in-process");
    if (auto st = check_reference_method(options.reference); !st)
      return bad_input("--reference: " + st.error());
  }
  if (diameter > 0) overrides.ball_diameter_m = diameter;
  if (snapshot_skew_ms >= 0)
    overrides.snapshot_skew_ns = static_cast<int64_t>(std::llround(snapshot_skew_ms * 1e6));
  if (!image_limit.empty()) {
    auto size = parse_size(image_limit);
    if (!size) return bad_input("--image-limit: " + size.error());
    overrides.image_limit = *size;
  }
  if (set_dir.empty())
    return bad_input(
        "no set: give --set DIR (a folder with left/, right/, ball_truth.csv, "
        "calibration/)");
  auto set = open_set(set_dir, truth, calibration);
  if (!set) return bad_input(set.error());
  if (!only_pairs.empty()) {
    std::vector<TruthRow> kept;
    for (const auto& id : only_pairs) {
      auto it = std::find_if(set->truth.begin(), set->truth.end(),
                             [&](const TruthRow& r) { return r.pair == id; });
      if (it == set->truth.end())
        return bad_input("--pairs: " + set->truth_path + " has no pair '" + id + "'");
      kept.push_back(*it);
    }
    set->truth = std::move(kept);
  }
  auto config = compose_detector_config(detector_base, overrides);
  if (!config) return bad_input(config.error());
  if (options.width_px % 2 != 0) return bad_input("--width-px must be even");
  const cv::Size limit = config->params.max_image_size();
  if (options.width_px == 0 &&
      (set->image_size.width > limit.width || set->image_size.height > limit.height)) {
    return bad_input(
        "the set's frames are " + std::to_string(set->image_size.width) + "x" +
        std::to_string(set->image_size.height) + " but the detector's image_limit is " +
        std::to_string(limit.width) + "x" + std::to_string(limit.height) +
        ": ball_detector would refuse every frame. Raise it: --image-limit " +
        std::to_string(set->image_size.width) + "x" + std::to_string(set->image_size.height) +
        " (or image_limit in --detector-config), or play smaller frames "
        "(--width-px)");
  }
  options.stop = &g_stop;
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  const RunResult run =
      in_process ? run_in_process(*set, *config, options) : run_dds(*set, *config, options);
  const auto scores = score_run(*set, run);
  const Summary summary = summarize(scores);
  ReportContext ctx{&*set, &*config, detector_base, options};
  std::cout << (json ? format_json(ctx, run, scores, summary)
                     : format_table(ctx, run, scores, summary, verbose));
  if (g_stop) return 130;
  return run.errors.empty() ? 0 : 1;
}
