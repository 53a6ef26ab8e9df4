#pragma once
// The calibration file: one OpenCV FileStorage YAML (or XML/JSON by
// extension) holding image size, K1 D1 K2 D2 R T R1 R2 P1 P2 Q, the RMS and
// per-pair errors. Written by stereoball-calibrate, read by every node.

#include "common/util/result.hpp"
#include "stereo/core/calibration.hpp"

#include <optional>
#include <string>
#include <vector>

namespace stereoball::stereo {

/// Extra, informational entries written beside the calibration (ignored when loading).
struct CalibrationFileInfo {
  double mean_rectified_row_error_px = -1;  ///< written if >= 0, pixels
  double square_size_m = -1;                ///< written if > 0, metres
  cv::Size board_inner_corners;             ///< written if non-empty
  std::vector<std::string> pair_names;      ///< written if non-empty
  std::string note;                         ///< free text, written if non-empty
};

/// Reads and validates a calibration file; the error names the file and the bad field.
Result<StereoCalibration> load_calibration(const std::string& path);

/// Parses calibration text (YAML/XML/JSON FileStorage content) and validates it.
Result<StereoCalibration> parse_calibration(const std::string& text);

/// Writes calib (and info) to path; the format follows the extension (.yaml/.yml/.xml/.json).
Status save_calibration(const std::string& path, const StereoCalibration& calib,
                        const CalibrationFileInfo& info = {});

/// The YAML text save_calibration would write.
std::string calibration_to_yaml(const StereoCalibration& calib,
                                const CalibrationFileInfo& info = {});

/// Reads OpenCV's stereo_calib.xml image list (<imagelist> of alternating left, right
/// names); relative names are resolved against the list's folder. Error if odd or empty.
Result<std::vector<std::pair<std::string, std::string>>> load_pair_list(const std::string& path);

}  // namespace stereoball::stereo
