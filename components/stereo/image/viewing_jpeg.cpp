#include "stereo/image/viewing_jpeg.hpp"

#include <turbojpeg.h>

#include <opencv2/imgproc.hpp>

#include <string>
#include <utility>

namespace stereoball::stereo {

ViewingJpegEncoder::~ViewingJpegEncoder() {
  if (compressor_) tjDestroy(compressor_);
}

ViewingJpegEncoder::ViewingJpegEncoder(ViewingJpegEncoder&& other) noexcept
    : compressor_(std::exchange(other.compressor_, nullptr)),
      scaled_(std::move(other.scaled_)),
      out_(std::move(other.out_)) {}

ViewingJpegEncoder& ViewingJpegEncoder::operator=(ViewingJpegEncoder&& other) noexcept {
  if (this != &other) {
    if (compressor_) tjDestroy(compressor_);
    compressor_ = std::exchange(other.compressor_, nullptr);
    scaled_ = std::move(other.scaled_);
    out_ = std::move(other.out_);
  }
  return *this;
}

Result<ViewingJpeg> ViewingJpegEncoder::encode(const cv::Mat& image, int max_width_px,
                                               int quality) {
  if (image.empty() || image.depth() != CV_8U || (image.channels() != 3 && image.channels() != 1))
    return Error{"JPEG encoding needs a non-empty 8-bit BGR or grey image"};
  cv::Mat shown = image;
  if (max_width_px > 0 && image.cols > max_width_px) {
    const double scale = static_cast<double>(max_width_px) / image.cols;
    cv::resize(image, scaled_, cv::Size(), scale, scale, cv::INTER_AREA);
    shown = scaled_;
  }
  if (!compressor_) compressor_ = tjInitCompress();
  if (!compressor_) return Error{std::string("cannot start the JPEG encoder: ") + tjGetErrorStr()};
  const bool grey = shown.channels() == 1;
  const int subsampling = grey ? TJSAMP_GRAY : TJSAMP_420;
  const size_t worst = tjBufSize(shown.cols, shown.rows, subsampling);
  if (out_.size() < worst) out_.resize(worst);
  unsigned char* dst = out_.data();
  unsigned long size = out_.size();
  // TJFLAG_NOREALLOC: the worst-case buffer is ours and reused from picture to picture.
  if (tjCompress2(compressor_, shown.data, shown.cols, static_cast<int>(shown.step), shown.rows,
                  grey ? TJPF_GRAY : TJPF_BGR, &dst, &size, subsampling, quality,
                  TJFLAG_NOREALLOC | TJFLAG_FASTDCT) != 0)
    return Error{std::string("JPEG encoding failed: ") + tjGetErrorStr2(compressor_)};
  return ViewingJpeg{{out_.data(), size}, shown.cols, shown.rows};
}

}  // namespace stereoball::stereo
