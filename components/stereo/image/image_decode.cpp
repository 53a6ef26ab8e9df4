#include "stereo/image/image_decode.hpp"

#include "stereo/image/jpeg_decompressor.hpp"

#include <jpeglib.h>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <array>

namespace stereoball::stereo {
namespace {

using jpeg_detail::JpegDecompressor;

constexpr std::array<std::uint8_t, 8> kPngMagic = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
// The IEND chunk every complete PNG ends with: length 0, type, CRC.
constexpr std::array<std::uint8_t, 12> kPngEnd = {0,   0,   0,    0,    'I',  'E',
                                                  'N', 'D', 0xAE, 0x42, 0x60, 0x82};
std::string dims(int w, int h) {
  return std::to_string(w) + "x" + std::to_string(h);
}

std::uint32_t load_be32(const std::uint8_t* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) |
         std::uint32_t{p[3]};
}

Result<ImageHeader> read_jpeg_header(std::span<const std::uint8_t> bytes) {
  JpegDecompressor jpeg;
  if (setjmp(jpeg.errors().jump)) {
    return Error{std::string("jpeg header is corrupt: ") + jpeg.errors().message.data()};
  }
  jpeg.read_header(bytes);
  return ImageHeader{ImageCodec::kJpeg, static_cast<int>(jpeg.info().image_width),
                     static_cast<int>(jpeg.info().image_height)};
}

Result<ImageHeader> read_png_header(std::span<const std::uint8_t> bytes) {
  // Signature, then the IHDR chunk: length 13, "IHDR", width, height (big-endian, 1..2^31-1).
  constexpr std::size_t kIhdrEnd = 8 + 8 + 13;
  if (bytes.size() < kIhdrEnd) return Error{"png header is truncated"};
  const std::uint8_t* chunk = bytes.data() + 8;
  if (load_be32(chunk) != 13 || !std::equal(chunk + 4, chunk + 8, "IHDR"))
    return Error{"png header is corrupt: the first chunk is not IHDR"};
  const std::uint32_t w = load_be32(chunk + 8), h = load_be32(chunk + 12);
  if (w == 0 || h == 0 || w > 0x7FFFFFFFu || h > 0x7FFFFFFFu)
    return Error{"png header is corrupt: size " + std::to_string(w) + "x" + std::to_string(h)};
  return ImageHeader{ImageCodec::kPng, static_cast<int>(w), static_cast<int>(h)};
}

Status decode_jpeg(std::span<const std::uint8_t> bytes, const ImageHeader& header, cv::Mat& out,
                   int reduction = 1) {
  JpegDecompressor jpeg;
  auto& info = jpeg.info();
  if (setjmp(jpeg.errors().jump)) {
    out.release();
    return Error{std::string("jpeg data is corrupt: ") + jpeg.errors().message.data()};
  }
  jpeg.read_header(bytes);
  if (static_cast<int>(info.image_width) != header.width_px ||
      static_cast<int>(info.image_height) != header.height_px) {
    out.release();
    return Error{"jpeg header changed between reads"};
  }
  info.out_color_space = JCS_EXT_BGR;  // libjpeg-turbo writes OpenCV's channel order directly
  info.scale_num = 1;
  info.scale_denom = static_cast<unsigned int>(reduction);
  jpeg_start_decompress(&info);
  if (static_cast<int>(info.output_width) != header.width_px / reduction ||
      static_cast<int>(info.output_height) != header.height_px / reduction) {
    out.release();
    return Error{"jpeg decoder cannot reduce by " + std::to_string(reduction)};
  }
  out.create(header.height_px / reduction, header.width_px / reduction, CV_8UC3);
  while (info.output_scanline < info.output_height) {
    JSAMPROW row = out.ptr<std::uint8_t>(static_cast<int>(info.output_scanline));
    jpeg_read_scanlines(&info, &row, 1);
  }
  jpeg_finish_decompress(&info);
  return {};
}

Status decode_png(std::span<const std::uint8_t> bytes, const ImageHeader& header, cv::Mat& out) {
  if (bytes.size() < kPngMagic.size() + kPngEnd.size() ||
      !std::equal(kPngEnd.begin(), kPngEnd.end(), bytes.end() - kPngEnd.size())) {
    out.release();
    return Error{"png data is truncated (no IEND chunk at the end)"};
  }
  const cv::Mat raw(1, static_cast<int>(bytes.size()), CV_8U,
                    const_cast<std::uint8_t*>(bytes.data()));
  try {
    cv::imdecode(raw, cv::IMREAD_COLOR, &out);
  } catch (const cv::Exception&) {
    out.release();
  }
  if (out.empty()) return Error{"png data is corrupt (libpng could not decode it)"};
  if (out.cols != header.width_px || out.rows != header.height_px) {
    out.release();
    return Error{"png header changed between reads"};
  }
  return {};
}

}  // namespace

const char* codec_name(ImageCodec codec) {
  return codec == ImageCodec::kJpeg ? "jpeg" : "png";
}

std::optional<ImageCodec> sniff_codec(std::span<const std::uint8_t> bytes) {
  if (bytes.size() >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8 && bytes[2] == 0xFF)
    return ImageCodec::kJpeg;
  if (bytes.size() >= kPngMagic.size() &&
      std::equal(kPngMagic.begin(), kPngMagic.end(), bytes.begin()))
    return ImageCodec::kPng;
  return std::nullopt;
}

Result<ImageHeader> read_image_header(std::span<const std::uint8_t> bytes) {
  const auto codec = sniff_codec(bytes);
  if (!codec) return Error{"not a jpeg or png image (" + std::to_string(bytes.size()) + " bytes)"};
  // libjpeg and OpenCV take the length as unsigned long / int.
  if (bytes.size() > static_cast<std::size_t>(INT32_MAX))
    return Error{"image stream is larger than 2 GiB"};
  return *codec == ImageCodec::kJpeg ? read_jpeg_header(bytes) : read_png_header(bytes);
}

Status check_within(const ImageHeader& header, cv::Size max_size) {
  if (header.width_px <= max_size.width && header.height_px <= max_size.height) return {};
  return Error{std::string(codec_name(header.codec)) + " header says " +
               dims(header.width_px, header.height_px) + ", larger than the limit " +
               dims(max_size.width, max_size.height)};
}

Status decode_bgr(std::span<const std::uint8_t> bytes, const ImageHeader& header, cv::Mat& out) {
  if (bytes.size() > static_cast<std::size_t>(INT32_MAX)) {
    out.release();
    return Error{"image stream is larger than 2 GiB"};
  }
  return header.codec == ImageCodec::kJpeg ? decode_jpeg(bytes, header, out)
                                           : decode_png(bytes, header, out);
}

bool decodes_reduced(const ImageHeader& header, int reduction) {
  return header.codec == ImageCodec::kJpeg &&
         (reduction == 2 || reduction == 4 || reduction == 8) && header.width_px % reduction == 0 &&
         header.height_px % reduction == 0;
}

Status decode_bgr_reduced(std::span<const std::uint8_t> bytes, const ImageHeader& header,
                          int reduction, cv::Mat& out) {
  if (!decodes_reduced(header, reduction)) {
    out.release();
    return Error{std::string(codec_name(header.codec)) + " image " +
                 dims(header.width_px, header.height_px) + " cannot be decoded reduced by " +
                 std::to_string(reduction)};
  }
  if (bytes.size() > static_cast<std::size_t>(INT32_MAX)) {
    out.release();
    return Error{"image stream is larger than 2 GiB"};
  }
  return decode_jpeg(bytes, header, out, reduction);
}

}  // namespace stereoball::stereo
