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
  image_.create(header.height_px / reduction, header.width_px / reduction, CV_8UC3);
  made_.assign(static_cast<std::size_t>(image_.rows), 0);
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

int LazyJpegEye::rows_made() const {
  return static_cast<int>(std::count(made_.begin(), made_.end(), std::uint8_t{1}));
}

Status LazyJpegEye::decode_ahead(const std::atomic<bool>& stop) {
  if (error_ || decoder_->scanline() != 0) return status();
  if (!read_rows(decoder_->jpeg, image_, image_.rows, &stop)) {
    fail();
    return status();
  }
  std::fill(made_.begin(), made_.begin() + decoder_->scanline(), std::uint8_t{1});
  return {};
}

bool LazyJpegEye::advance(int begin_row, int end_row) {
  int row = decoder_->scanline();
  while (row < end_row) {
    // A run of rows to decode (asked for, not made), or of rows to pass over.
    const bool decode = row >= begin_row && made_[row] == 0;
    int run_end = row + 1;
    while (run_end < end_row && (run_end >= begin_row && made_[run_end] == 0) == decode) ++run_end;
    if (decode) {
      if (!read_rows(decoder_->jpeg, image_, run_end, nullptr)) return false;
      std::fill(made_.begin() + row, made_.begin() + run_end, std::uint8_t{1});
    } else if (!skip_rows(decoder_->jpeg, run_end - row)) {
      return false;
    }
    row = run_end;
  }
  return true;
}

void LazyJpegEye::make_rows(int begin_row, int end_row) {
  begin_row = std::max(begin_row, 0);
  end_row = std::min(end_row, image_.rows);
  if (error_ || begin_row >= end_row) return;
  const auto first = std::find(made_.begin() + begin_row, made_.begin() + end_row, 0);
  if (first == made_.begin() + end_row) return;  // made already
  // Rows above the decoder's place: decode again from the top (passing over the rows made).
  const int first_row = static_cast<int>(first - made_.begin());
  if (first_row < decoder_->scanline() && !restart()) return fail();
  if (!advance(first_row, end_row)) fail();
}

void LazyJpegEye::fail() {
  if (!error_)
    error_ = eye_ + " jpeg data is corrupt: " + (decoder_ ? decoder_->message() : std::string("?"));
  // Rows never made are zero from now on: whatever reads them reads the same thing each time.
  for (int r = 0; r < image_.rows; ++r)
    if (made_[static_cast<std::size_t>(r)] == 0) image_.row(r).setTo(0);
  std::fill(made_.begin(), made_.end(), std::uint8_t{1});
  decoder_.reset();
}

Status LazyJpegEye::status() const {
  if (error_) return Error{*error_};
  return {};
}

}  // namespace stereoball::stereo
