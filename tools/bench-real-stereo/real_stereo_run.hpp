#pragma once
// Plays a real stereo set through the ball detector and collects one detection per pair:
// over DDS with the real camera_server and ball_detector processes (run_dds, the default and
// what acceptance figures use), or with the detector's pipeline library in this process on the
// same frames and conversions (run_in_process, for fast tuning loops).

#include <atomic>
#include <optional>
#include <string>
#include <vector>

#include "real_stereo_score.hpp"
#include "real_stereo_set.hpp"
#include "stereoball.h"

namespace stereoball::real_stereo {

/// How the frames are played.
struct RunOptions {
  std::string frame_encoding = "jpeg";  ///< camera_server frame_encoding: raw | jpeg | png
  int jpeg_quality = 90;                ///< with jpeg
  std::string jpeg_chroma = "444";      ///< camera_server jpeg_chroma: 444 | 422 | 420
  int width_px = 0;                     ///< camera_server publish_width_px (0 = native)
  double rate_hz = 1.0;                 ///< camera_server playback rate (DDS)
  int domain = 87;                      ///< private DDS domain (DDS)
  std::string partition;                ///< DDS partition ("" = one made from the pid)
  std::string bin_dir;                  ///< folder of camera_server and ball_detector
  double start_timeout_s = 20.0;        ///< a node's start (decode, discovery), s
  double pair_timeout_s = 20.0;         ///< longest wait for the answers after the last frame, s
  double warmup_s = 10.0;  ///< DDS: the first pair is played this long first (not scored), s
  bool retry = true;       ///< play the pairs without a detection once more
  /// in-process: a circle detector of the factory ("edcircles", ...) also run on every decoded
  /// left eye, rectified, alone, and timed beside the pipeline ("" = none)
  std::string reference;
  const std::atomic<bool>* stop = nullptr;  ///< set by SIGINT/SIGTERM: tear down and fail
};

/// One played pair's answer.
struct PairRun {
  std::optional<Detection> detection;  ///< nullopt: no detection came (a run error)
  int attempts = 0;                    ///< plays of the pair (2 after a retry)
};

/// CPU time one search of the detector took over a run (in-process only).
struct SearchCpu {
  std::string path;  ///< the search ("whole_frame", ...; "decode": the eyes' JPEG/PNG; "other":
                     ///< shrinking, checks, patch)
  double total_ms = 0.0;  ///< its own thread CPU time over every frame, ms (nested searches apart)
  int frames = 0;         ///< frames that ran it
};

/// Everything a run produced.
struct RunResult {
  std::string mode;                 ///< "dds" or "in-process"
  std::vector<PairRun> pairs;       ///< per truth row, in the set's order
  std::vector<std::string> errors;  ///< run errors (no detection, refused frames, node failures)
  std::vector<std::string> notes;   ///< what the user should know (retries, node logs' gist)
  double scale = 1.0;               ///< published width / set width (truth scaled by it)
  cv::Size played_size;             ///< frame size the detector saw
  std::vector<SearchCpu> cpu_by_search;  ///< in-process: where the detector's CPU time went
  std::vector<std::optional<ReferenceFrame>> reference;  ///< per truth row (RunOptions::reference)
};

/// The scorer's view of a ball/detection sample (the same for both paths).
Detection detection_from_message(const stereoball_msg_BallDetection& msg);

/// Lower-case name of a ball/detection status ("found", "no_candidate", ...).
std::string status_name(stereoball_msg_DetectionStatus status);

/// Statuses that mean the detector did not look at the frame (refused calibration or frame):
/// a run error, never a miss.
bool is_refusal(stereoball_msg_DetectionStatus status);

/// The pipeline library in this process: every pair decoded as camera_server does, encoded and
/// decoded as the frame travels (frame_encoding), calibration through its message with the
/// detector's image limit, one pipeline for the whole set in its order (as the node keeps one).
RunResult run_in_process(const RealStereoSet& set, const DetectorConfig& config,
                         const RunOptions& options);

/// Whether run_in_process knows the reference method (the circle detector factory's names).
Status check_reference_method(const std::string& method);

/// camera_server (file source) and ball_detector as processes on a private domain.
RunResult run_dds(const RealStereoSet& set, const DetectorConfig& config,
                  const RunOptions& options);

}  // namespace stereoball::real_stereo
