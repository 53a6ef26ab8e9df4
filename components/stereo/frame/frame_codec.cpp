#include "stereo/frame/frame_codec.hpp"

#include <jpeglib.h>

#include <opencv2/imgcodecs.hpp>

#include <csetjmp>
#include <cstdlib>

namespace stereoball::stereo {
namespace {

// libjpeg reports errors through error_exit, which must not return: jump back to the caller.
struct JpegErrors {
  jpeg_error_mgr base;
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
};

[[noreturn]] void on_jpeg_error(j_common_ptr cinfo) {
  auto* errors = reinterpret_cast<JpegErrors*>(cinfo->err);
  (*cinfo->err->format_message)(cinfo, errors->message);
  std::longjmp(errors->jump, 1);
}

// How many luma samples share one chroma sample, across and down.
struct ChromaSampling {
  int h = 1;
  int v = 1;
};

ChromaSampling chroma_sampling(const std::string& jpeg_chroma) {
  if (jpeg_chroma == "422") return {2, 1};
  if (jpeg_chroma == "420") return {2, 2};
  return {1, 1};
}

// One JPEG stream of an 8-bit grey or BGR image in *out (malloc'ed by libjpeg; the caller
// frees it), the chroma subsampled by sampling (grey has no chroma). C-style on purpose:
// nothing with a destructor lives between setjmp and longjmp. False on failure,
// errors.message says why.
bool compress_jpeg(const cv::Mat& image, int quality, ChromaSampling sampling, unsigned char** out,
                   unsigned long* size, JpegErrors& errors) {
  jpeg_compress_struct cinfo;
  cinfo.err = jpeg_std_error(&errors.base);
  errors.base.error_exit = on_jpeg_error;
  if (setjmp(errors.jump)) {
    jpeg_destroy_compress(&cinfo);
    return false;
  }
  jpeg_create_compress(&cinfo);
  jpeg_mem_dest(&cinfo, out, size);
  cinfo.image_width = static_cast<JDIMENSION>(image.cols);
  cinfo.image_height = static_cast<JDIMENSION>(image.rows);
  cinfo.input_components = image.channels();
  cinfo.in_color_space = image.channels() == 3 ? JCS_EXT_BGR : JCS_GRAYSCALE;
  jpeg_set_defaults(&cinfo);
  jpeg_set_quality(&cinfo, quality, TRUE);
  // optimize_coding would save ~5 % of the bytes for 3x the encode time (2.2 -> 6.6 ms a pair).
  cinfo.optimize_coding = FALSE;
  // libjpeg subsamples by giving luma more samples per MCU than the two chroma components.
  for (int c = 0; c < cinfo.num_components; ++c) {
    const bool luma_of_colour = c == 0 && cinfo.num_components == 3;
    cinfo.comp_info[c].h_samp_factor = luma_of_colour ? sampling.h : 1;
    cinfo.comp_info[c].v_samp_factor = luma_of_colour ? sampling.v : 1;
  }
  jpeg_start_compress(&cinfo, TRUE);
  while (cinfo.next_scanline < cinfo.image_height) {
    JSAMPROW row = const_cast<JSAMPLE*>(image.ptr<JSAMPLE>(static_cast<int>(cinfo.next_scanline)));
    jpeg_write_scanlines(&cinfo, &row, 1);
  }
  jpeg_finish_compress(&cinfo);
  jpeg_destroy_compress(&cinfo);
  return true;
}

}  // namespace

const std::vector<std::string>& frame_encoding_choices() {
  static const std::vector<std::string> kChoices{"raw", "jpeg", "png"};
  return kChoices;
}

const std::vector<std::string>& jpeg_chroma_choices() {
  static const std::vector<std::string> kChoices{"444", "422", "420"};
  return kChoices;
}

const params::FieldTable<FrameCodecParams>& frame_codec_fields() {
  using params::at;
  const FrameCodecParams defaults;
  static const params::FieldTable<FrameCodecParams> table{{
      params::choice("frame_encoding", at(&FrameCodecParams::frame_encoding),
                     defaults.frame_encoding, frame_encoding_choices(),
                     "raw (pixels) or jpeg / png: how each eye is compressed before publishing"),
      params::number("jpeg_quality", at(&FrameCodecParams::jpeg_quality), defaults.jpeg_quality,
                     {1, 100}, "", "JPEG quality, used with frame_encoding jpeg"),
      params::choice("jpeg_chroma", at(&FrameCodecParams::jpeg_chroma), defaults.jpeg_chroma,
                     jpeg_chroma_choices(),
                     "colour resolution of JPEG eyes: 444 full, 422 half the columns, 420 half "
                     "the columns and rows (fewer bytes, less encode and decode work)"),
      params::number("preview_max_width_px", at(&FrameCodecParams::preview_max_width_px),
                     defaults.preview_max_width_px, {0, 8192}, "px",
                     "stereo/preview (for stereoball view, encoded only while a viewer reads "
                     "it): eyes scaled to at most this width; 0 = no preview"),
      params::number("preview_jpeg_quality", at(&FrameCodecParams::preview_jpeg_quality),
                     defaults.preview_jpeg_quality, {1, 100}, "",
                     "JPEG quality of stereo/preview (4:2:0)"),
  }};
  return table;
}

Status FrameCodecParams::validate() const {
  return params::check_fields(frame_codec_fields(), *this);
}

EyeEncoder::EyeEncoder(const FrameCodecParams& params) : params_(params) {}

Status EyeEncoder::encode(const cv::Mat& image) {
  if (image.empty()) return Error{"cannot " + params_.frame_encoding + "-encode an empty image"};
  if (image.type() != CV_8UC1 && image.type() != CV_8UC3) {
    return Error{"cannot " + params_.frame_encoding +
                 "-encode this image: only 8-bit grey or BGR images are supported"};
  }
  if (params_.frame_encoding == "jpeg") return encode_jpeg(image);
  bool ok = false;
  try {
    ok = cv::imencode(".png", image, bytes_, {cv::IMWRITE_PNG_COMPRESSION, kPngCompressionLevel});
  } catch (const cv::Exception& e) {
    return Error{std::string("png encoding failed: ") + e.what()};
  }
  if (!ok || bytes_.empty()) return Error{"png encoding failed"};
  return {};
}

Status EyeEncoder::encode_jpeg(const cv::Mat& image) {
  unsigned char* out = nullptr;
  unsigned long size = 0;
  JpegErrors errors{};
  const bool ok = compress_jpeg(image, params_.jpeg_quality, chroma_sampling(params_.jpeg_chroma),
                                &out, &size, errors);
  if (ok) bytes_.assign(out, out + size);
  std::free(out);
  if (!ok) return Error{std::string("jpeg encoding failed: ") + errors.message};
  return {};
}

}  // namespace stereoball::stereo
