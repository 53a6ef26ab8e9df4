#pragma once
// Internal to stereo/image: a libjpeg decompressor reading from memory whose errors, and
// warnings (corrupt or truncated data libjpeg would paper over), jump back to the caller's
// setjmp with the message; a progressive stream's scans are capped.

// jpeglib.h uses size_t and FILE without including their headers.
#include <cstddef>
#include <cstdio>

#include <jpeglib.h>

#include <array>
#include <csetjmp>
#include <cstdint>
#include <span>

namespace stereoball::stereo::jpeg_detail {

// A progressive JPEG may hold any number of scans, each costing a pass over the image; real
// encoders write about ten. The cap keeps a crafted stream from costing seconds.
inline constexpr int kMaxJpegScans = 64;

// libjpeg reports errors through callbacks; this one jumps back with the message, and also
// turns warnings (corrupt or truncated data that libjpeg would paper over) into errors.
struct JpegErrors {
  jpeg_error_mgr mgr{};
  jpeg_progress_mgr progress{};
  std::jmp_buf jump{};
  std::array<char, JMSG_LENGTH_MAX> message{};
};

[[noreturn]] inline void jpeg_fail(j_common_ptr cinfo) {
  auto* errors = reinterpret_cast<JpegErrors*>(cinfo->err);
  (*cinfo->err->format_message)(cinfo, errors->message.data());
  std::longjmp(errors->jump, 1);
}

inline void jpeg_message(j_common_ptr cinfo, int level) {
  if (level < 0) jpeg_fail(cinfo);  // a warning: the data is corrupt or truncated
}

inline void jpeg_scan_limit(j_common_ptr cinfo) {
  auto* d = reinterpret_cast<j_decompress_ptr>(cinfo);
  if (d->is_decompressor && d->input_scan_number > kMaxJpegScans) {
    auto* errors = reinterpret_cast<JpegErrors*>(cinfo->err);
    std::snprintf(errors->message.data(), errors->message.size(), "more than %d scans",
                  kMaxJpegScans);
    std::longjmp(errors->jump, 1);
  }
}

// Owns a decompressor reading from memory with the error handling above.
class JpegDecompressor {
 public:
  JpegDecompressor() {
    info_.err = jpeg_std_error(&errors_.mgr);
    errors_.mgr.error_exit = jpeg_fail;
    errors_.mgr.emit_message = jpeg_message;
    errors_.progress.progress_monitor = jpeg_scan_limit;
    jpeg_create_decompress(&info_);
    info_.progress = &errors_.progress;
  }
  /// Reads the header of bytes; may longjmp to errors().jump, so call it after setjmp.
  void read_header(std::span<const std::uint8_t> bytes) {
    jpeg_mem_src(&info_, bytes.data(), static_cast<unsigned long>(bytes.size()));
    jpeg_read_header(&info_, TRUE);
  }
  ~JpegDecompressor() { jpeg_destroy_decompress(&info_); }
  JpegDecompressor(const JpegDecompressor&) = delete;
  JpegDecompressor& operator=(const JpegDecompressor&) = delete;

  jpeg_decompress_struct& info() { return info_; }
  JpegErrors& errors() { return errors_; }

 private:
  jpeg_decompress_struct info_{};
  JpegErrors errors_;
};

}  // namespace stereoball::stereo::jpeg_detail
