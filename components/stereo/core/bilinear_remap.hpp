#pragma once
// The rectification's bilinear look-up (cv::remap with fixed-point maps) for colour frames,
// faster than OpenCV 4.6's own, which does not vectorise three channels.

#include <opencv2/core.hpp>

namespace stereoball::stereo {

/// dst = cv::remap(src, xy, frac, INTER_LINEAR, BORDER_CONSTANT, 0) bit for bit: xy CV_16SC2
/// integer source pixels and frac CV_16UC1 5+5-bit fractions (cv::convertMaps, or
/// initUndistortRectifyMap with CV_16SC2). CV_8UC3 images take the fast path, anything else
/// (and src sharing memory with dst) goes to cv::remap. dst may be a view (a region of a
/// larger image): only its own pixels are written.
void remap_bilinear(const cv::Mat& src, cv::Mat& dst, const cv::Mat& xy, const cv::Mat& frac);

/// How remap_bilinear works at most: the plain loop, its SSSE3 path, or its AVX2 path (two
/// pixels at a time), each where the CPU has it (else the next slower, then cv::remap).
enum class RemapPath { kPlain, kSsse3, kAvx2 };

/// remap_bilinear by the given path: the same bits whichever runs (tests compare them).
void remap_bilinear(const cv::Mat& src, cv::Mat& dst, const cv::Mat& xy, const cv::Mat& frac,
                    RemapPath fastest);

}  // namespace stereoball::stereo
