#pragma once
// A real stereo set on disk (README.md, "The set folder"): left/ and right/ images, the truth
// CSV, the rig's calibration YAML; and the detector configuration a run uses (the shipped file
// with the user's overrides), as YAML text both paths read.

#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "ball_detector/pipeline/detector_params.hpp"
#include "common/util/result.hpp"
#include "real_stereo_score.hpp"

namespace stereoball::real_stereo {

/// The files of a set, checked to exist.
struct RealStereoSet {
  std::string dir;               ///< the set's folder
  std::string truth_path;        ///< the truth CSV
  std::string calibration_path;  ///< the rig's calibration YAML
  std::vector<TruthRow> truth;   ///< one row per pair, in file order
  cv::Size image_size;           ///< size of every image (the first pair's, checked on read)
  std::string left_path(const TruthRow& row) const { return dir + "/left/" + row.left; }
  std::string right_path(const TruthRow& row) const { return dir + "/right/" + row.right; }
};

/// Opens the set in dir: truth from truth_path (else dir/ball_truth.csv), calibration from
/// calibration_path (else the one *.yaml in dir/calibration/). Every image a truth row names
/// must exist. Errors name the file at fault.
Result<RealStereoSet> open_set(const std::string& dir, const std::string& truth_path = "",
                               const std::string& calibration_path = "");

/// Reads and parses a truth CSV (errors "FILE:LINE: what").
Result<std::vector<TruthRow>> load_truth(const std::string& path);

/// What the user changes in the shipped detector configuration.
struct DetectorOverrides {
  std::string config_file;                ///< YAML merged over the shipped file ("" = none)
  std::optional<double> ball_diameter_m;  ///< ball.diameter_m
  bool no_floor_check = false;            ///< floor.tolerance_m: 0
  std::optional<cv::Size> image_limit;    ///< image_limit.max_width_px / max_height_px
  /// epipolar.skew_ns for stills whose frames carry no capture-stamp difference, ns
  std::optional<int64_t> snapshot_skew_ns;
};

/// The detector configuration of a run: YAML text (the node reads it from a file) and the
/// parameters it gives (the in-process path uses them).
struct DetectorConfig {
  std::string yaml;
  ball_detector::BallDetectorParams params;
  std::vector<std::string> changes;  ///< "key: value (from ...)" for every override applied
  /// "dotted.key: value" for every value of the override file that differs from the shipped one
  std::vector<std::string> changed_keys;
};

/// shipped_path's YAML, the override file's keys merged over it (mappings merged, anything else
/// replaced), then the flags; validated as ball_detector validates its file.
Result<DetectorConfig> compose_detector_config(const std::string& shipped_path,
                                               const DetectorOverrides& overrides);

/// Parses "WxH" (e.g. "2304x1296").
Result<cv::Size> parse_size(const std::string& text);

}  // namespace stereoball::real_stereo
