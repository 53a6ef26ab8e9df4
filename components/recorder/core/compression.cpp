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
    return std::string("zstd compression failed: ") + ZSTD_getErrorName(n);
  }
  out.resize(start + n);
  return std::nullopt;
}

size_t zstd_bound(size_t n) {
  return ZSTD_compressBound(n);
}

Status zstd_decompress(std::span<const uint8_t> input, uint64_t expected_size,
                       std::vector<uint8_t>& out) {
  // Guards against a corrupt size field asking for an absurd allocation.
  constexpr uint64_t kMaxChunkBytes = uint64_t{4} << 30;
  if (expected_size > kMaxChunkBytes) {
    return "chunk uncompressed size " + std::to_string(expected_size) + " is implausible";
  }
  out.resize(expected_size);
  const size_t n = ZSTD_decompress(out.data(), out.size(), input.data(), input.size());
  if (ZSTD_isError(n)) return std::string("zstd decompression failed: ") + ZSTD_getErrorName(n);
  if (n != expected_size) {
    return "zstd produced " + std::to_string(n) + " bytes, chunk header says " +
           std::to_string(expected_size);
  }
  return std::nullopt;
}

}  // namespace stereoball::recorder
