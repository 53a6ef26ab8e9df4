#include "recorder/core/compression.hpp"

#include <zstd.h>

namespace stereoball::recorder {

struct ZstdCompressor::Impl {
  ZSTD_CCtx* cctx = ZSTD_createCCtx();
  ~Impl() { ZSTD_freeCCtx(cctx); }
};

ZstdCompressor::ZstdCompressor(int level) : impl_(std::make_unique<Impl>()) {
  ZSTD_CCtx_setParameter(impl_->cctx, ZSTD_c_compressionLevel, level);
  // A checksum would duplicate the chunk's uncompressed CRC.
  ZSTD_CCtx_setParameter(impl_->cctx, ZSTD_c_checksumFlag, 0);
}

ZstdCompressor::~ZstdCompressor() = default;

Status ZstdCompressor::compress(std::span<const uint8_t> input, std::vector<uint8_t>& out) {
  const size_t start = out.size();
  out.resize(start + ZSTD_compressBound(input.size()));
  const size_t n = ZSTD_compress2(impl_->cctx, out.data() + start, out.size() - start, input.data(),
                                  input.size());
  if (ZSTD_isError(n)) {
    out.resize(start);
    return Error{std::string("zstd compression failed: ") + ZSTD_getErrorName(n)};
  }
  out.resize(start + n);
  return {};
}

size_t zstd_bound(size_t n) {
  return ZSTD_compressBound(n);
}

Status zstd_decompress(std::span<const uint8_t> input, uint64_t expected_size,
                       std::vector<uint8_t>& out, uint64_t max_bytes) {
  // The chunk header's size is only a claim: check it against the limit and against the zstd
  // frame's own record of its content before allocating for it.
  if (expected_size > max_bytes) {
    return Error{"chunk claims " + std::to_string(expected_size) +
                 " bytes uncompressed, more than the reader's limit of " +
                 std::to_string(max_bytes)};
  }
  const unsigned long long frame_size = ZSTD_getFrameContentSize(input.data(), input.size());
  if (frame_size == ZSTD_CONTENTSIZE_ERROR) return Error{"not a zstd frame"};
  if (frame_size != ZSTD_CONTENTSIZE_UNKNOWN && frame_size != expected_size) {
    return Error{"zstd frame holds " + std::to_string(frame_size) + " bytes, chunk header says " +
                 std::to_string(expected_size)};
  }
  out.resize(expected_size);
  const size_t n = ZSTD_decompress(out.data(), out.size(), input.data(), input.size());
  if (ZSTD_isError(n))
    return Error{std::string("zstd decompression failed: ") + ZSTD_getErrorName(n)};
  if (n != expected_size) {
    return Error{"zstd produced " + std::to_string(n) + " bytes, chunk header says " +
                 std::to_string(expected_size)};
  }
  return {};
}

}  // namespace stereoball::recorder
