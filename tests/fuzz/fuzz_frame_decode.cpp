// libFuzzer target: frame decoding. Either a compressed eye (JPEG/PNG header, size check,
// strict decode) or a whole stereo/frame sample through the frame library's FrameDecoder with
// raw (bgr8/mono8), yuyv (converted) or compressed eyes, arbitrary size, step and length
// fields, and JPEG eyes decoded at full size or reduced by 2, 4 or 8.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "fuzz_input.hpp"
#include "stereo/frame/frame_decoder.hpp"
#include "stereo/image/image_decode.hpp"

namespace {

const char* const kEncodings[] = {"bgr8", "mono8", "jpeg", "png", "yuyv", ""};
const int kReductions[] = {1, 2, 4, 8};

void decode_image(const std::vector<uint8_t>& bytes) {
  namespace st = stereoball::stereo;
  const auto header = st::read_image_header(bytes);
  if (!header || !st::check_within(*header, {640, 480})) return;
  cv::Mat out;
  (void)st::decode_bgr(bytes, *header, out);
}

void fill_eye(stereoball::fuzz::FuzzInput& in, std::vector<uint8_t>& bytes,
              stereoball_msg_EyeImage& eye) {
  eye.width_px = in.take<uint8_t>();  // small sizes keep each run fast; limits are tested
  eye.height_px = in.take<uint8_t>();
  eye.step_bytes = in.take<uint16_t>();
  bytes = in.bytes(1 << 16);
  eye.data._buffer = bytes.empty() ? nullptr : bytes.data();
  eye.data._length = eye.data._maximum = static_cast<uint32_t>(bytes.size());
}

void decode_frame(stereoball::fuzz::FuzzInput& in) {
  stereoball_msg_StereoFrame msg{};
  msg.encoding = const_cast<char*>(kEncodings[in.choice(std::size(kEncodings))]);
  const cv::Size expected(in.take<uint8_t>() + 1, in.take<uint8_t>() + 1);
  std::vector<uint8_t> left, right;
  fill_eye(in, left, msg.left);
  fill_eye(in, right, msg.right);
  stereoball::stereo::FrameDecoder decoder;
  // Taken last, so the corpus's inputs keep their eyes (one that has run out: full size).
  decoder.set_reduction(kReductions[in.choice(std::size(kReductions))]);
  cv::Mat l, r;
  if (decoder.decode(msg, expected, l, r).ok()) {
    // Touch every pixel: a view past the sample's bytes would be caught here.
    volatile int sum = 0;
    sum = sum + static_cast<int>(cv::sum(l)[0] + cv::sum(r)[0]);
  }
  // The right eye decoded lazily: a middle band first, then the rows above it (decoded again
  // from the top), then all of it.
  stereoball::stereo::RowSource* lazy = nullptr;
  const auto in_turn = [](int n, const std::function<void(int)>& task) {
    for (int i = 0; i < n; ++i) task(i);
  };
  if (decoder.decode_right_lazily(msg, expected, l, lazy, in_turn).ok()) {
    const int rows = lazy->image().rows;
    lazy->make_rows(rows / 2, rows / 2 + 1);
    lazy->make_rows(0, rows / 4 + 1);
    lazy->make_all();
    volatile int sum = 0;
    sum = sum + static_cast<int>(cv::sum(lazy->image())[0]);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  stereoball::fuzz::FuzzInput in(data, size);
  if (in.flag()) {
    decode_image(in.rest());
  } else {
    decode_frame(in);
  }
  return 0;
}
