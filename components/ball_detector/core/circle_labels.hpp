#pragma once
// Ground-truth circle labels of real photographs (tests/data/circles/*.circles): parsing only,
// the caller reads the file. Format, one item per line, '#' starts a comment:
//   image <path relative to the project root>     exactly once
//   split tune|report                               exactly once
//   circle <x_px> <y_px> <radius_px>                any number (pixel centres on integers)
//   min_radius <px>                                 at most once: every circle of at least this
//                                                   radius is labelled (default: the reader's)

#include "ball_detector/core/circle.hpp"

#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace stereoball::ball_detector {

/// Which part of the labelled set an image belongs to.
enum class LabelSplit { tune, report };

/// The labels of one image.
struct CircleLabels {
  std::string image_path;  ///< as written in the file (relative to the project root)
  LabelSplit split = LabelSplit::tune;
  std::vector<Circle> circles;  ///< score 1
  /// The smallest radius down to which every circle was labelled, when the file states it.
  std::optional<double> min_radius_px;
};

/// Parses the text of one label file; source names it in errors ("<source>:<line>: ...").
/// Returns the labels or the first error.
std::variant<CircleLabels, std::string> parse_circle_labels(std::string_view text,
                                                            const std::string& source);

/// "tune" or "report".
const char* split_name(LabelSplit split);

}  // namespace stereoball::ball_detector
