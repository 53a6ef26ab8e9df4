#include "stereo/image/lazy_jpeg_eye.hpp"

#include "stereo/image/jpeg_decompressor.hpp"

#include <algorithm>

namespace stereoball::stereo {
namespace {

using jpeg_detail::JpegDecompressor;

// The functions that call setjmp hold nothing with a destructor: libjpeg's errors longjmp
// back into them.

// Reads the header and starts decompressing at 1/reduction; false on an error.
bool begin_decoding(JpegDecompressor& jpeg, std::span<const std::uint8_t> bytes, int reduction) {
  jpeg_decompress_struct& info = jpeg.info();
  if (setjmp(jpeg.errors().jump)) return false;
  jpeg.read_header(bytes);
  info.out_color_space = JCS_EXT_BGR;  // libjpeg-turbo writes OpenCV's channel order directly
  info.scale_num = 1;
  info.scale_denom = static_cast<unsigned int>(reduction);
  jpeg_start_decompress(&info);
  return true;
}

// Decodes rows into image until end_row (or stop is set); finishes the stream after its last
// row (libjpeg then reads on to the EOI marker, where damage at the end shows). False on an
// error.
bool read_rows(JpegDecompressor& jpeg, cv::Mat& image, int end_row, const std::atomic<bool>* stop) {
  jpeg_decompress_struct& info = jpeg.info();
  if (setjmp(jpeg.errors().jump)) return false;
  while (static_cast<int>(info.output_scanline) < end_row &&
         (stop == nullptr || !stop->load(std::memory_order_relaxed))) {
    JSAMPROW row = image.ptr<std::uint8_t>(static_cast<int>(info.output_scanline));
    jpeg_read_scanlines(&info, &row, 1);
  }
  if (info.output_scanline == info.output_height) jpeg_finish_decompress(&info);
  return true;
}

// Passes over rows rows without making their pixels (their data is still read). False on an
// error.
bool skip_rows(JpegDecompressor& jpeg, int rows) {
  jpeg_decompress_struct& info = jpeg.info();
  if (setjmp(jpeg.errors().jump)) return false;
  jpeg_skip_scanlines(&info, static_cast<JDIMENSION>(rows));
  return true;
}

// Whether bytes end in the EOI marker every complete JPEG stream ends with.
bool ends_with_eoi(std::span<const std::uint8_t> bytes) {
  return bytes.size() >= 2 && bytes[bytes.size() - 2] == 0xFF && bytes.back() == 0xD9;
}

}  // namespace

struct LazyJpegEye::Decoder {
  JpegDecompressor jpeg;
  std::string message() { return jpeg.errors().message.data(); }
  int scanline() { return static_cast<int>(jpeg.info().output_scanline); }
};

LazyJpegEye::LazyJpegEye() = default;
LazyJpegEye::~LazyJpegEye() = default;

Status LazyJpegEye::start(const std::string& eye, std::span<const std::uint8_t> bytes,
                          const ImageHeader& header, int reduction) {
  eye_ = eye;
  bytes_ = bytes;
  header_ = header;
  reduction_ = reduction;
  error_.reset();
  made_begin_ = made_end_ = 0;
  image_.create(header.height_px / reduction, header.width_px / reduction, CV_8UC3);
  if (!restart()) {
    fail();
    return status();
  }
  // A truncated stream is refused before any search reads it, as a whole decode refuses it.
  if (!ends_with_eoi(bytes)) make_all();
  return status();
}

bool LazyJpegEye::restart() {
  decoder_ = std::make_unique<Decoder>();
  if (!begin_decoding(decoder_->jpeg, bytes_, reduction_)) return false;
  const jpeg_decompress_struct& info = decoder_->jpeg.info();
  if (static_cast<int>(info.image_width) != header_.width_px ||
      static_cast<int>(info.image_height) != header_.height_px) {
    error_ = eye_ + " jpeg header changed between reads";
    return false;
  }
  if (static_cast<int>(info.output_width) != image_.cols ||
      static_cast<int>(info.output_height) != image_.rows) {
    error_ = eye_ + " jpeg decoder cannot reduce by " + std::to_string(reduction_);
    return false;
  }
  return true;
}

bool LazyJpegEye::read_to(int end_row, const std::atomic<bool>* stop) {
  return read_rows(decoder_->jpeg, image_, end_row, stop);
}

bool LazyJpegEye::skip_to(int row) {
  const int rows = row - decoder_->scanline();
  return rows <= 0 || skip_rows(decoder_->jpeg, rows);
}

Status LazyJpegEye::decode_ahead(const std::atomic<bool>& stop) {
  if (error_ || made_begin_ != 0) return status();
  if (!read_to(image_.rows, &stop)) {
    fail();
    return status();
  }
  made_end_ = decoder_->scanline();
  return {};
}

void LazyJpegEye::make_rows(int begin_row, int end_row) {
  begin_row = std::max(begin_row, 0);
  end_row = std::min(end_row, image_.rows);
  if (error_ || begin_row >= end_row) return;
  if (begin_row >= made_begin_ && end_row <= made_end_) return;
  if (made_begin_ == made_end_) {
    // Nothing made yet: the rows above the first ones read are passed over.
    if (!skip_to(begin_row)) return fail();
    made_begin_ = made_end_ = begin_row;
  } else if (begin_row < made_begin_) {
    // Rows above those made: decode again from the top down to them, then pass over the rows
    // made already (the same bytes) back to where decoding stood.
    const int lowest = made_end_;
    if (!restart() || !skip_to(begin_row) || !read_to(made_begin_, nullptr)) return fail();
    if (lowest < image_.rows && !skip_to(lowest)) return fail();
    made_begin_ = begin_row;
  }
  // Rows between those made and those asked for are decoded too: the made rows stay one run.
  if (end_row > made_end_) {
    if (!read_to(end_row, nullptr)) return fail();
    made_end_ = end_row;
  }
}

void LazyJpegEye::fail() {
  if (!error_)
    error_ = eye_ + " jpeg data is corrupt: " + (decoder_ ? decoder_->message() : std::string("?"));
  // Rows never made are zero from now on: whatever reads them reads the same thing each time.
  image_.rowRange(0, made_begin_).setTo(0);
  image_.rowRange(made_end_, image_.rows).setTo(0);
  made_begin_ = 0;
  made_end_ = image_.rows;
  decoder_.reset();
}

Status LazyJpegEye::status() const {
  if (error_) return Error{*error_};
  return {};
}

}  // namespace stereoball::stereo
