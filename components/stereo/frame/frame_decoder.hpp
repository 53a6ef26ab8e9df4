#pragma once
// Checks a stereo/frame sample against the calibration and turns it into two images:
// zero-copy views for bgr8/mono8, decoded buffers (reused) for jpeg/png.

#include <opencv2/core.hpp>

#include <optional>
#include <string>

#include "common/util/result.hpp"
#include "stereoball.h"

namespace stereoball::stereo {

/// Pixel encodings the detector accepts.
enum class FrameEncoding { kBgr8, kMono8, kJpeg, kPng };

/// The encoding named by text, or nullopt for an unsupported one.
std::optional<FrameEncoding> parse_encoding(const char* text);

/// Whether a raw (bgr8/mono8) eye can be used: step, length and size checks; errors say why.
Status check_raw_eye(const char* eye, const stereoball_msg_EyeImage& image, int channels,
                     cv::Size expected);

/// Validates and decodes StereoFrame samples; owns the decode buffers.
class FrameDecoder {
 public:
  /// Fills left/right (CV_8UC3 BGR or CV_8UC1) for a frame that must have size expected.
  /// Raw encodings give views of msg's bytes (valid while msg lives); compressed ones give
  /// views of this decoder's buffers (valid until the next call). Error names eye and problem.
  Status decode(const stereoball_msg_StereoFrame& msg, cv::Size expected, cv::Mat& left,
                cv::Mat& right);

 private:
  Status decode_eye(const char* eye, const stereoball_msg_EyeImage& image, FrameEncoding encoding,
                    cv::Size expected, cv::Mat& buffer, cv::Mat& out);

  cv::Mat decoded_left_, decoded_right_;
};

}  // namespace stereoball::stereo
