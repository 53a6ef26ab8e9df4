// Test support: a stereo/frame sample built from two images, owning the bytes and strings it
// points at, so tests can send it, spoil one field at a time and decode it.
#pragma once

#include <opencv2/imgcodecs.hpp>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "stereoball.h"

namespace stereoball::stereo::testing {

struct FrameSampleBuilder {
  std::string encoding = "bgr8";
  std::string source = "test";
  std::vector<uint8_t> left, right;
  stereoball_msg_StereoFrame msg{};

  /// Both eyes as raw pixels (step = width x element size), under the current encoding.
  FrameSampleBuilder& raw(const cv::Mat& l, const cv::Mat& r) {
    left.assign(l.data, l.data + l.total() * l.elemSize());
    right.assign(r.data, r.data + r.total() * r.elemSize());
    describe(msg.left, left, l.cols, l.rows, static_cast<uint32_t>(l.cols * l.elemSize()));
    describe(msg.right, right, r.cols, r.rows, static_cast<uint32_t>(r.cols * r.elemSize()));
    return *this;
  }

  /// Both eyes compressed by OpenCV; ext "png" or "jpg" (encoding "png" or "jpeg").
  FrameSampleBuilder& encoded(const std::string& ext, const cv::Mat& l, const cv::Mat& r) {
    cv::imencode("." + ext, l, left);
    cv::imencode("." + ext, r, right);
    encoding = ext == "jpg" ? "jpeg" : ext;
    describe(msg.left, left, l.cols, l.rows, 0);
    describe(msg.right, right, r.cols, r.rows, 0);
    return *this;
  }

  /// Both eyes as the given JPEG streams of images of size (encoding "jpeg").
  FrameSampleBuilder& jpeg(std::vector<uint8_t> l, std::vector<uint8_t> r, cv::Size size) {
    left = std::move(l);
    right = std::move(r);
    encoding = "jpeg";
    describe(msg.left, left, size.width, size.height, 0);
    describe(msg.right, right, size.width, size.height, 0);
    return *this;
  }

  /// The sample, its pointers renewed (this builder may have been copied since it was filled);
  /// sizes and lengths stay as the test left them.
  const stereoball_msg_StereoFrame& get() {
    msg.encoding = encoding.data();
    msg.source = source.data();
    msg.left.data._buffer = left.data();
    msg.right.data._buffer = right.data();
    return msg;
  }

 private:
  static void describe(stereoball_msg_EyeImage& eye, std::vector<uint8_t>& bytes, int w, int h,
                       uint32_t step) {
    eye.width_px = static_cast<uint32_t>(w);
    eye.height_px = static_cast<uint32_t>(h);
    eye.step_bytes = step;
    eye.data._buffer = bytes.data();
    eye.data._length = eye.data._maximum = static_cast<uint32_t>(bytes.size());
  }
};

}  // namespace stereoball::stereo::testing
