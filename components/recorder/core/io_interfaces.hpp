#pragma once
// Byte sink (where the writer puts a file) and byte source (where the reader gets one).
// The core only defines them and in-memory versions; files live in recorder/io.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "common/util/result.hpp"

namespace stereoball::recorder {

/// Destination of an MCAP byte stream, written strictly sequentially.
class Sink {
 public:
  virtual ~Sink() = default;
  /// Appends bytes; returns an error message when they could not all be written.
  virtual Status write(std::span<const uint8_t> bytes) = 0;
  /// Makes everything written so far durable against a crash of this process.
  virtual Status flush() { return {}; }
};

/// Sink that keeps the bytes in memory (tests, benchmarks).
class MemorySink : public Sink {
 public:
  Status write(std::span<const uint8_t> bytes) override {
    bytes_.insert(bytes_.end(), bytes.begin(), bytes.end());
    return {};
  }
  /// Everything written so far.
  const std::vector<uint8_t>& bytes() const { return bytes_; }

 private:
  std::vector<uint8_t> bytes_;
};

/// Scratch storage written sequentially and read back later: the writer keeps the summary's
/// chunk indexes there rather than in memory, so a recording of any length holds a bounded
/// amount of memory.
class Spill : public Sink {
 public:
  /// Bytes written so far.
  virtual uint64_t size() const = 0;
  /// Reads exactly out.size() bytes at offset; error when that range was not written.
  virtual Status read(uint64_t offset, std::span<uint8_t> out) = 0;
};

/// Spill that keeps the bytes in memory (tests).
class MemorySpill : public Spill {
 public:
  Status write(std::span<const uint8_t> bytes) override {
    bytes_.insert(bytes_.end(), bytes.begin(), bytes.end());
    return {};
  }
  uint64_t size() const override { return bytes_.size(); }
  Status read(uint64_t offset, std::span<uint8_t> out) override;

 private:
  std::vector<uint8_t> bytes_;
};

/// Random-access origin of an MCAP byte stream.
class Source {
 public:
  virtual ~Source() = default;
  /// Total size in bytes.
  virtual uint64_t size() const = 0;
  /// Reads exactly out.size() bytes at offset; error when that range is not available.
  virtual Status read(uint64_t offset, std::span<uint8_t> out) = 0;
};

/// Source over a buffer owned by the caller.
class MemorySource : public Source {
 public:
  /// Reads from bytes, which must outlive the source.
  explicit MemorySource(std::span<const uint8_t> bytes) : bytes_(bytes) {}
  uint64_t size() const override { return bytes_.size(); }
  Status read(uint64_t offset, std::span<uint8_t> out) override;

 private:
  std::span<const uint8_t> bytes_;
};

}  // namespace stereoball::recorder
