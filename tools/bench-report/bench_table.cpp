#include "bench_table.hpp"

namespace stereoball::bench_report {

const std::vector<BenchEntry>& bench_table() {
  // Order: the system as a user runs it first, then closed loop, tracking, detector alone,
  // transport and tools. `cheap`: a few minutes on a shared 2-core machine.
  static const std::vector<BenchEntry> kTable = {
      {"real-stereo",
       "Real stereo pairs through the running system, published at half width",
       "stereoball-bench-real-stereo",
       {"--ball-diameter-m", "0.24", "--no-floor-check", "--snapshot-skew-ms", "16.7", "--width-px",
        "1152", "--rate-hz", "0.5"},
       false,
       "camera_server (publish_width_px 1152) -> ball_detector as processes over DDS on real "
       "stereo pairs with a person's ground truth: correct, wrong and missed pairs, by row "
       "misalignment, time.",
       "shared/data/real-stereo-basketball (a basketball, an unsynchronised rig; recorded by "
       "others). The detector's settings were chosen on its odd-numbered pairs; the even ones "
       "were not tuned on.",
       true},
      {"real-stereo-full",
       "Real stereo pairs through the running system, full 2304x1296",
       "stereoball-bench-real-stereo",
       {"--ball-diameter-m", "0.24", "--no-floor-check", "--snapshot-skew-ms", "16.7",
        "--image-limit", "2304x1296", "--rate-hz", "0.25"},
       false,
       "As real-stereo, at the sensor's full size.",
       "shared/data/real-stereo-basketball; settings chosen on its odd-numbered pairs.",
       true},
      {"real-stereo-reference",
       "Real stereo pairs in-process beside EDCircles on the left eye alone",
       "stereoball-bench-real-stereo",
       {"--ball-diameter-m", "0.24", "--no-floor-check", "--snapshot-skew-ms", "16.7", "--width-px",
        "1152", "--in-process", "--reference", "edcircles"},
       false,
       "The detector's CPU time per 1152x648 stereo frame on one core, and in the same run "
       "EDCircles (OpenCV's Edge Drawing) on each frame's rectified left eye alone plus the "
       "frame's decode: how far a time target is from the best known method on these frames.",
       "shared/data/real-stereo-basketball; the detector's settings chosen on its odd-numbered "
       "pairs; EDCircles at the node's radius range, nothing tuned.",
       true},
      {"closed-loop",
       "Closed loop on the built-in scenarios",
       "stereoball-bench-closed-loop",
       {"--jobs", "2"},
       true,
       "Issue 7 acceptance at simulated time, every scenario x 3 seeds: (a) ball kept within "
       "tolerance of the reachable time, (b) leave events turned the right way and reacquired, "
       "(c) no following without a ball.",
       "config/scenarios (built-in scenes; the controller's settings were chosen on them).",
       true},
      {"tracking",
       "Detection and tracking on the built-in scenarios",
       "stereoball-bench-tracking",
       {"--drive", "controller"},
       false,
       "Detector + tracker on every frame with the motion controller driving: track accepted "
       "with the ball visible, false acceptance without a ball, 3D error, detector time.",
       "config/scenarios (built-in scenes; detector settings were chosen on them).",
       true},
      {"composite",
       "Real stereo backgrounds with a composited ball",
       "stereoball-bench-composite",
       {"--seed", "99"},
       false,
       "Stereo pipeline on OpenCV's real chessboard pairs and Middlebury Aloe with a shaded "
       "ball drawn in at known 3D positions: found, false detections, 3D error.",
       "shared/data/opencv-samples; seed 99 was not tuned on (seed 17 was).",
       true},
      {"detect-photos",
       "Circle detectors on labelled real photographs",
       "stereoball-bench-detect",
       {"--no-synthetic"},
       false,
       "Pixel-to-Pixel against OpenCV HOUGH_GRADIENT_ALT and EDCircles on labelled photographs: "
       "F1 on the tune and report splits, time per image.",
       "tests/data/circles (44 photographs, 340 circles nobody on the team made; settings chosen "
       "on the tune split only).",
       true},
      {"latency",
       "Exposure to velocity command (separate processes, one host)",
       "stereoball-bench-latency",
       {"--runs", "1"},
       true,
       "Simulator -> ball_detector -> tracker -> motion_controller as processes: per-stage and "
       "end-to-end latency, raw and JPEG frames, 30 and 60 Hz.",
       "Simulator scenario ball_rolling_across (looped).",
       true},
      {"detect",
       "Circle detectors on synthetic scenes and real timing images",
       "stereoball-bench-detect",
       {"--no-cht"},
       false,
       "Pixel-to-Pixel against OpenCV HOUGH_GRADIENT, HOUGH_GRADIENT_ALT, EDCircles and "
       "gradient voting: F1, centre error, time at 640x480.",
       "Synthetic scenes (seeded) and shared/data/opencv-samples for timing.",
       false},
      {"tracking-development",
       "Randomised worlds: the 12 development sets",
       "stereoball-bench-tracking",
       {"--drive", "controller", "--randomize", "12",   "--jobs", "2",   "--seed", "101",
        "--seed",  "202",        "--seed",      "303",  "--seed", "404", "--seed", "505",
        "--seed",  "606",        "--seed",      "707",  "--seed", "808", "--seed", "909",
        "--seed",  "1111",       "--seed",      "1212", "--seed", "1313"},
       false,
       "Detection and tracking on 144 randomised scenes, per scene, per category and in total.",
       "config/randomize.yaml, seeds 101-1313: the detector's settings were chosen on them.",
       false},
      {"tracking-report-sets",
       "Randomised worlds: sets not tuned on",
       "stereoball-bench-tracking",
       {"--drive", "controller", "--randomize", "12", "--jobs", "2", "--seed", "2909", "--seed",
        "6661", "--seed", "8117"},
       false,
       "As above on 36 scenes nothing was chosen on.",
       "config/randomize.yaml, seeds 2909, 6661, 8117 (run once after settings were chosen).",
       false},
      {"closed-loop-development",
       "Closed loop in randomised worlds (development sets)",
       "stereoball-bench-closed-loop",
       {"--jobs", "2",    "--seeds", "1",    "--randomize", "12",  "--seed", "101",
        "--seed", "202",  "--seed",  "303",  "--seed",      "404", "--seed", "505",
        "--seed", "606",  "--seed",  "707",  "--seed",      "808", "--seed", "909",
        "--seed", "1111", "--seed",  "1212", "--seed",      "1313"},
       true,
       "Closed-loop acceptance (a), (b), (c) on 144 randomised scenes.",
       "config/randomize.yaml, development seeds (tuned on).",
       false},
      {"transport",
       "Frame transport over DDS",
       "stereoball-bench-transport",
       {},
       false,
       "stereo/frame samples between two processes: rate, latency, against ddsperf.",
       "Rendered frames.",
       false},
      {"auth",
       "Message authentication cost",
       "stereoball-bench-auth",
       {},
       false,
       "Sign/verify time per sample and DDS round trips with and without authentication.",
       "Synthetic samples.",
       false},
      {"viewer",
       "What the viewer costs",
       "stereoball-bench-viewer",
       {},
       false,
       "Viewer and robot CPU with 0/1/2/5 clients and a headless Chromium, capture -> client "
       "latency, memory.",
       "The demo's simulator.",
       false},
      {"camera",
       "camera_server's conversions",
       "stereoball-bench-camera",
       {"--seconds", "3"},
       false,
       "YUYV to BGR against cv::cvtColor, MJPEG decode, the file source's core path.",
       "Synthetic camera buffers.",
       true},
      {"camera-node",
       "camera_server as a process over DDS",
       "stereoball-bench-camera-node",
       {"--seconds", "10"},
       false,
       "The real camera_server process publishing files: tick to sample received, node CPU.",
       "Rendered image files (loopback Cyclone configuration).",
       false},
      {"stereo",
       "Stereo geometry",
       "stereoball-bench-stereo",
       {},
       false,
       "LUT build, rectification of a 640x480 pair, point rectification, depth error against "
       "its bound, the Aloe row check.",
       "Synthetic rig and shared/data/opencv-samples (Aloe).",
       true},
      {"render",
       "Simulator rendering",
       "stereoball-sim-bench",
       {"--frames", "300"},
       false,
       "Rendering a 640x480 stereo pair of ball_rolling_across; full step with noise and ground "
       "truth.",
       "Built-in scenario ball_rolling_across.",
       true},
      {"jpeg-accuracy",
       "Detection on JPEG frames",
       "stereoball-bench-jpeg-accuracy",
       {"--frames", "40", "--spacing", "0.1", "--quality", "85", "90", "95"},
       false,
       "Ball detector on raw frames and on JPEG copies: bytes per pair, found, centre and 3D "
       "shift, error against the truth.",
       "Built-in scenarios rendered by the simulator core.",
       false},
      {"distributed",
       "Frames and the system between two hosts",
       "stereoball-bench-distributed",
       {},
       false,
       "Frame transport between two network namespaces (raw and JPEG, default and capped "
       "receive buffers) and the robot/workstation profiles end to end. Needs root.",
       "Rendered frames; built-in scenario.",
       false},
  };
  return kTable;
}

const BenchEntry* find_bench(const std::string& name) {
  for (const auto& e : bench_table()) {
    if (e.name == name) return &e;
  }
  return nullptr;
}

std::string user_command(const BenchEntry& entry) {
  // `stereoball A B ...` runs `stereoball-A-B`, so the program's name is the command.
  std::string command = entry.program;
  const std::string bench = "stereoball-bench-", tool = "stereoball-";
  if (command.rfind(bench, 0) == 0) {
    command = "stereoball bench " + command.substr(bench.size());
  } else if (command.rfind(tool, 0) == 0) {
    command = "stereoball " + command.substr(tool.size());
  }
  for (const auto& a : entry.args) command += " " + a;
  return command;
}

}  // namespace stereoball::bench_report
