#pragma once
// zstd compression of chunk records (the only compression this recorder writes or reads).

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "common/util/result.hpp"

namespace stereoball::recorder {

/// Reusable zstd compressor (keeps its context between chunks).
class ZstdCompressor {
 public:
  /// level: zstd level (1 = fastest useful, 19 = smallest).
  explicit ZstdCompressor(int level);
  ~ZstdCompressor();
  ZstdCompressor(const ZstdCompressor&) = delete;
  ZstdCompressor& operator=(const ZstdCompressor&) = delete;
  /// Appends the compressed form of input to out.
  Status compress(std::span<const uint8_t> input, std::vector<uint8_t>& out);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Upper bound of the compressed size of n input bytes.
size_t zstd_bound(size_t n);

/// Decompresses a chunk's records into out (resized to expected_size); error when the stream is
/// corrupt or does not produce exactly expected_size bytes. Nothing is allocated when
/// expected_size exceeds max_bytes or differs from the size the zstd frame header records.
Status zstd_decompress(std::span<const uint8_t> input, uint64_t expected_size,
                       std::vector<uint8_t>& out, uint64_t max_bytes);

}  // namespace stereoball::recorder
