#pragma once
// Checks a stereo/frame sample against the calibration and turns it into two images:
// zero-copy views for bgr8/mono8, converted or decoded buffers (reused) for yuyv/jpeg/png.

#include <opencv2/core.hpp>

#include <functional>
#include <optional>
#include <string>

#include "common/util/result.hpp"
#include "stereo/core/row_source.hpp"
#include "stereo/image/lazy_jpeg_eye.hpp"
#include "stereoball.h"

namespace stereoball::stereo {

/// Pixel encodings the detector accepts.
enum class FrameEncoding { kBgr8, kMono8, kYuyv, kJpeg, kPng };

/// The encoding named by text, or nullopt for an unsupported one.
std::optional<FrameEncoding> parse_encoding(const char* text);

/// Whether a raw (bgr8/mono8/yuyv: channels 3/1/2) eye can be used: step, length and size
/// checks; errors say why.
Status check_raw_eye(const char* eye, const stereoball_msg_EyeImage& image, int channels,
                     cv::Size expected);

/// Validates and decodes StereoFrame samples; owns the decode buffers.
class FrameDecoder {
 public:
  /// Fills left/right (CV_8UC3 BGR or CV_8UC1) for a frame that must have size expected.
  /// bgr8/mono8 give views of msg's bytes (valid while msg lives); yuyv (converted to BGR by
  /// stereo/image/yuyv_convert, as camera_server does) and compressed ones give views of this
  /// decoder's buffers (valid until the next call). Error names eye and problem;
  /// left and right are then both empty (a refused frame has no usable eye).
  Status decode(const stereoball_msg_StereoFrame& msg, cv::Size expected, cv::Mat& left,
                cv::Mat& right);

  /// Runs task(0) .. task(n - 1), possibly at the same time, and returns once all are done.
  using RunTasks = std::function<void(int n, const std::function<void(int)>& task)>;
  /// As decode, the two eyes as two tasks of run (each touches only its own eye's buffer): the
  /// same images and the same error (the left eye's first), in less time when run spreads them
  /// over two cores.
  Status decode(const stereoball_msg_StereoFrame& msg, cv::Size expected, cv::Mat& left,
                cv::Mat& right, const RunTasks& run);

  /// As decode(msg, expected, left, right, run), the right eye as rows made when first read
  /// (valid until the next call; nullptr on an error): a JPEG right eye is decoded only as far
  /// as its reader makes rows (stereo/image/lazy_jpeg_eye.hpp), beforehand only as far as the
  /// second task gets while the left eye decodes; any other right eye is whole. A JPEG eye's
  /// corrupt data below the rows decoded here shows in right->status() once reached.
  Status decode_right_lazily(const stereoball_msg_StereoFrame& msg, cv::Size expected,
                             cv::Mat& left, RowSource*& right, const RunTasks& run);

  /// From now on, JPEG eyes whose size reduction divides (decodes_reduced) are decoded at
  /// 1/reduction of expected (a consumer that shrinks them by that factor anyway); other eyes
  /// keep their size (bgr8, mono8 and yuyv eyes too: the consumer shrinks them). 1 (the
  /// default) = every eye at its own size.
  void set_reduction(int reduction) { reduction_ = reduction; }

 private:
  Status decode_eye(const char* eye, const stereoball_msg_EyeImage& image, FrameEncoding encoding,
                    cv::Size expected, cv::Mat& buffer, cv::Mat& out);
  /// The header of a compressed eye, checked against the frame's encoding and expected.
  Result<ImageHeader> compressed_header(const char* eye, const stereoball_msg_EyeImage& image,
                                        FrameEncoding encoding, cv::Size expected) const;
  Status convert_yuyv_eye(const char* eye, const stereoball_msg_EyeImage& image, cv::Size expected,
                          cv::Mat& buffer, cv::Mat& out);

  cv::Mat decoded_left_, decoded_right_;
  cv::Mat right_view_;                         // decode_right_lazily's whole right eye
  std::optional<WholeImageRows> whole_right_;  // ... as rows
  LazyJpegEye lazy_right_;
  int reduction_ = 1;
};

}  // namespace stereoball::stereo
