#pragma once
// Stereo pairs from image files (left/right globs or a folder of left*/right* pairs), decoded
// once at start so playback costs no disk or decode time.

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "camera_server/core/status.hpp"

namespace stereoball::camera_server {

/// Where the files are and how to decode them.
struct FileSourceParams {
  std::string left_glob;             ///< e.g. "data/left*.jpg" (with right_glob)
  std::string right_glob;            ///< e.g. "data/right*.jpg"
  std::string pairs_dir;             ///< or: folder whose files named *left* pair with *right*
  std::string encoding = "as_read";  ///< "as_read" (mono8 or bgr8 as stored), "bgr8", "mono8"
};

/// One decoded pair.
struct FilePair {
  std::string left_path;
  std::string right_path;
  cv::Mat left;  ///< CV_8UC1 (mono8) or CV_8UC3 (bgr8), continuous
  cv::Mat right;
};

/// All pairs, same size and encoding.
class FileSource {
 public:
  /// Finds, pairs and decodes the files; the error names the glob, folder or file at fault.
  static Result<FileSource> open(const FileSourceParams& params);

  /// Number of pairs.
  size_t size() const { return pairs_.size(); }
  /// Pair i (0 <= i < size()).
  const FilePair& pair(size_t i) const { return pairs_[i]; }
  /// "mono8" or "bgr8".
  const std::string& encoding() const { return encoding_; }
  /// Image size shared by all pairs, pixels.
  cv::Size image_size() const { return pairs_.front().left.size(); }
  /// Description for StereoFrame.source, e.g. "files:data/left*.jpg+data/right*.jpg".
  const std::string& description() const { return description_; }

 private:
  std::vector<FilePair> pairs_;
  std::string encoding_;
  std::string description_;
};

}  // namespace stereoball::camera_server
