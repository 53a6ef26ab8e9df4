#include "stereo/frame/frame_decoder.hpp"

#include <atomic>
#include <cstring>
#include <limits>
#include <span>
#include <string_view>

#include "stereo/image/image_decode.hpp"
#include "stereo/image/yuyv_convert.hpp"

namespace stereoball::stereo {
namespace {

std::string dims(std::uint64_t w, std::uint64_t h) {
  return std::to_string(w) + "x" + std::to_string(h);
}

Status check_size(const char* eye, std::uint64_t w, std::uint64_t h, cv::Size expected) {
  if (w == static_cast<std::uint64_t>(expected.width) &&
      h == static_cast<std::uint64_t>(expected.height))
    return {};
  return Error{std::string(eye) + " image is " + dims(w, h) + " but the calibration is for " +
               dims(static_cast<std::uint64_t>(expected.width),
                    static_cast<std::uint64_t>(expected.height))};
}

Error unsupported_encoding(const stereoball_msg_StereoFrame& msg) {
  return Error{"encoding '" + std::string(msg.encoding ? msg.encoding : "") +
               "' is not supported (bgr8, mono8, yuyv, jpeg, png)"};
}

// A refused frame gives no images: the good eye of a broken pair is no frame, and nothing
// downstream may take it for one.
Status refused_if_failed(Status status, cv::Mat& left, cv::Mat& right) {
  if (!status) {
    left.release();
    right.release();
  }
  return status;
}

}  // namespace

std::optional<FrameEncoding> parse_encoding(const char* text) {
  if (text == nullptr) return std::nullopt;
  if (std::strcmp(text, "bgr8") == 0) return FrameEncoding::kBgr8;
  if (std::strcmp(text, "mono8") == 0) return FrameEncoding::kMono8;
  if (std::strcmp(text, "yuyv") == 0) return FrameEncoding::kYuyv;
  if (std::strcmp(text, "jpeg") == 0) return FrameEncoding::kJpeg;
  if (std::strcmp(text, "png") == 0) return FrameEncoding::kPng;
  return std::nullopt;
}

Status check_raw_eye(const char* eye, const stereoball_msg_EyeImage& image, int channels,
                     cv::Size expected) {
  if (auto st = check_size(eye, image.width_px, image.height_px, expected); !st) return st;
  const std::uint64_t min_step = std::uint64_t{image.width_px} * static_cast<unsigned>(channels);
  if (image.step_bytes < min_step)
    return Error{std::string(eye) + " step_bytes " + std::to_string(image.step_bytes) +
                 " is smaller than width * channels = " + std::to_string(min_step)};
  const std::uint64_t need = std::uint64_t{image.step_bytes} * image.height_px;
  if (image.data._length != need || image.data._buffer == nullptr)
    return Error{std::string(eye) + " image has " + std::to_string(image.data._length) +
                 " data bytes, expected step * height = " + std::to_string(need) +
                 (image.data._length < need ? " (truncated)" : "")};
  return {};
}

Status FrameDecoder::decode(const stereoball_msg_StereoFrame& msg, cv::Size expected, cv::Mat& left,
                            cv::Mat& right) {
  const auto encoding = parse_encoding(msg.encoding);
  Status status = encoding ? decode_eye("left", msg.left, *encoding, expected, decoded_left_, left)
                           : unsupported_encoding(msg);
  if (status) status = decode_eye("right", msg.right, *encoding, expected, decoded_right_, right);
  return refused_if_failed(std::move(status), left, right);
}

Status FrameDecoder::decode(const stereoball_msg_StereoFrame& msg, cv::Size expected, cv::Mat& left,
                            cv::Mat& right, const RunTasks& run) {
  const auto encoding = parse_encoding(msg.encoding);
  if (!encoding) return refused_if_failed(unsupported_encoding(msg), left, right);
  // bgr8/mono8 eyes are views, nothing to share out; yuyv and compressed eyes are work.
  if (*encoding == FrameEncoding::kBgr8 || *encoding == FrameEncoding::kMono8)
    return decode(msg, expected, left, right);
  Status status[2];
  run(2, [&](int eye) {
    status[eye] = eye == 0
                      ? decode_eye("left", msg.left, *encoding, expected, decoded_left_, left)
                      : decode_eye("right", msg.right, *encoding, expected, decoded_right_, right);
  });
  return refused_if_failed(status[0] ? status[1] : status[0], left, right);
}

Status FrameDecoder::decode_right_lazily(const stereoball_msg_StereoFrame& msg, cv::Size expected,
                                         cv::Mat& left, RowSource*& right, const RunTasks& run) {
  right = nullptr;
  const auto encoding = parse_encoding(msg.encoding);
  if (encoding != FrameEncoding::kJpeg) {
    Status st = decode(msg, expected, left, right_view_, run);
    if (st) right = &whole_right_.emplace(right_view_);
    return st;
  }
  // The left eye whole; the right one started and decoded from the top on the second task
  // until the left eye is done (run in turn, the left goes first: nothing ahead of the search).
  std::atomic<bool> left_done{false};
  Status status[2];
  run(2, [&](int eye) {
    if (eye == 0) {
      status[0] = decode_eye("left", msg.left, *encoding, expected, decoded_left_, left);
      left_done = true;
      return;
    }
    const auto header = compressed_header("right", msg.right, *encoding, expected);
    if (!header) {
      status[1] = Error{header.error()};
      return;
    }
    const int reduction = reduction_ > 1 && decodes_reduced(*header, reduction_) ? reduction_ : 1;
    const std::span<const std::uint8_t> bytes(msg.right.data._buffer, msg.right.data._length);
    status[1] = lazy_right_.start("right", bytes, *header, reduction);
    if (status[1]) status[1] = lazy_right_.decode_ahead(left_done);
  });
  Status st = status[0] ? status[1] : status[0];
  if (!st) {
    left.release();
    return st;
  }
  right = &lazy_right_;
  return st;
}

Result<ImageHeader> FrameDecoder::compressed_header(const char* eye,
                                                    const stereoball_msg_EyeImage& image,
                                                    FrameEncoding encoding,
                                                    cv::Size expected) const {
  const char* name = encoding == FrameEncoding::kJpeg ? "jpeg" : "png";
  if (auto st = check_size(eye, image.width_px, image.height_px, expected); !st)
    return Error{st.error()};
  if (image.data._length == 0 || image.data._buffer == nullptr)
    return Error{std::string(eye) + " " + name + " data is empty"};
  const std::span<const std::uint8_t> bytes(image.data._buffer, image.data._length);
  // The header is read and checked before anything is decoded: the size fields of the
  // sample are only claims, the header decides how much memory decoding takes.
  auto header = stereo::read_image_header(bytes);
  if (!header) return Error{std::string(eye) + " " + name + " data: " + header.error()};
  if (std::string_view(stereo::codec_name(header->codec)) != name)
    return Error{std::string(eye) + " image is " + stereo::codec_name(header->codec) +
                 " data in a " + name + " frame"};
  if (cv::Size(header->width_px, header->height_px) != expected)
    return Error{std::string(eye) + " " + name + " header says " +
                 dims(static_cast<std::uint64_t>(header->width_px),
                      static_cast<std::uint64_t>(header->height_px)) +
                 " but the calibration is for " +
                 dims(static_cast<std::uint64_t>(expected.width),
                      static_cast<std::uint64_t>(expected.height))};
  return header;
}

Status FrameDecoder::decode_eye(const char* eye, const stereoball_msg_EyeImage& image,
                                FrameEncoding encoding, cv::Size expected, cv::Mat& buffer,
                                cv::Mat& out) {
  if (encoding == FrameEncoding::kBgr8 || encoding == FrameEncoding::kMono8) {
    const int channels = encoding == FrameEncoding::kBgr8 ? 3 : 1;
    if (auto st = check_raw_eye(eye, image, channels, expected); !st) return st;
    out = cv::Mat(static_cast<int>(image.height_px), static_cast<int>(image.width_px),
                  CV_8UC(channels), image.data._buffer, image.step_bytes);
    return {};
  }
  if (encoding == FrameEncoding::kYuyv) return convert_yuyv_eye(eye, image, expected, buffer, out);
  const auto header = compressed_header(eye, image, encoding, expected);
  if (!header) return Error{header.error()};
  const std::span<const std::uint8_t> bytes(image.data._buffer, image.data._length);
  const Status decoded = reduction_ > 1 && stereo::decodes_reduced(*header, reduction_)
                             ? stereo::decode_bgr_reduced(bytes, *header, reduction_, buffer)
                             : stereo::decode_bgr(bytes, *header, buffer);
  if (!decoded) return Error{std::string(eye) + " " + decoded.error()};
  out = buffer;
  return {};
}

Status FrameDecoder::convert_yuyv_eye(const char* eye, const stereoball_msg_EyeImage& image,
                                      cv::Size expected, cv::Mat& buffer, cv::Mat& out) {
  if (auto st = check_raw_eye(eye, image, 2, expected); !st) return st;
  // YUYV carries one U and one V per two pixels: an odd width has no last pair.
  if (image.width_px % 2 != 0)
    return Error{std::string(eye) + " yuyv width " + std::to_string(image.width_px) +
                 " is odd (YUYV pairs two pixels)"};
  if (image.step_bytes > static_cast<std::uint32_t>(std::numeric_limits<int>::max()))
    return Error{std::string(eye) + " step_bytes " + std::to_string(image.step_bytes) +
                 " is too large"};
  const std::span<const std::uint8_t> bytes(image.data._buffer, image.data._length);
  const Status converted = stereo::yuyv_to_bgr(bytes, static_cast<int>(image.width_px),
                                               static_cast<int>(image.height_px),
                                               static_cast<int>(image.step_bytes), buffer);
  if (!converted) return Error{std::string(eye) + " " + converted.error()};
  out = buffer;
  return {};
}

}  // namespace stereoball::stereo
