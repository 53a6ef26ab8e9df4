#pragma once
// Test support of the detector core's fast-path tests: the real sample images and the Sobel
// derivatives the references are computed from.

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <filesystem>
#include <system_error>
#include <vector>

namespace stereoball::ball_detector {

/// The real sample images (../shared/data/opencv-samples), read with imread flags.
inline std::vector<cv::Mat> real_images(int flags) {
  std::vector<cv::Mat> out;
  const std::filesystem::path dir = std::filesystem::path(SB_SHARED_DATA_DIR) / "opencv-samples";
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
    const auto ext = e.path().extension();
    if (ext != ".png" && ext != ".jpg") continue;
    cv::Mat m = cv::imread(e.path().string(), flags);
    if (!m.empty()) out.push_back(m);
  }
  return out;
}

/// The real sample images in grey.
inline std::vector<cv::Mat> real_greys() {
  return real_images(cv::IMREAD_GRAYSCALE);
}

/// The real sample images in colour.
inline std::vector<cv::Mat> real_colours() {
  return real_images(cv::IMREAD_COLOR);
}

/// 3x3 Sobel derivatives with replicated borders (the detector's own).
inline void sobel(const cv::Mat& grey, cv::Mat& dx, cv::Mat& dy) {
  cv::Sobel(grey, dx, CV_16S, 1, 0, 3, 1.0, 0.0, cv::BORDER_REPLICATE);
  cv::Sobel(grey, dy, CV_16S, 0, 1, 3, 1.0, 0.0, cv::BORDER_REPLICATE);
}

}  // namespace stereoball::ball_detector
