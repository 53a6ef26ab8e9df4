#pragma once
// Files as MCAP sinks and sources (POSIX write/pread, no user-space buffering).

#include <cstdint>
#include <memory>
#include <string>

#include "common/util/result.hpp"
#include "recorder/core/io_interfaces.hpp"

namespace stereoball::recorder {

/// Writes a new file sequentially. Each write() goes straight to the kernel, so everything
/// written survives a crash (SIGKILL) of this process; flush() additionally fdatasyncs when
/// sync_on_flush is set (survives power loss, costs throughput).
class FileSink : public Sink {
 public:
  /// Creates (truncates) path; error when it cannot be opened for writing.
  static Result<std::unique_ptr<FileSink>> create(const std::string& path,
                                                  bool sync_on_flush = false);
  ~FileSink() override;
  FileSink(const FileSink&) = delete;
  FileSink& operator=(const FileSink&) = delete;
  Status write(std::span<const uint8_t> bytes) override;
  Status flush() override;
  /// Waits until everything written is on the device (fdatasync).
  Status sync();

 private:
  FileSink(int fd, std::string path, bool sync_on_flush)
      : fd_(fd), path_(std::move(path)), sync_on_flush_(sync_on_flush) {}
  int fd_;
  std::string path_;
  bool sync_on_flush_;
};

/// A spill in an unnamed temporary file (no name in any directory, so it disappears when the
/// process ends, however it ends).
class FileSpill : public Spill {
 public:
  /// Creates the file in dir (the recording's own directory, so it lives on the same disk);
  /// error names dir and the reason.
  static Result<std::unique_ptr<FileSpill>> create(const std::string& dir);
  ~FileSpill() override;
  FileSpill(const FileSpill&) = delete;
  FileSpill& operator=(const FileSpill&) = delete;
  Status write(std::span<const uint8_t> bytes) override;
  uint64_t size() const override { return size_; }
  Status read(uint64_t offset, std::span<uint8_t> out) override;

 private:
  FileSpill(int fd, std::string dir) : fd_(fd), dir_(std::move(dir)) {}
  int fd_;
  std::string dir_;
  uint64_t size_ = 0;
};

/// Reads an existing file at random offsets.
class FileSource : public Source {
 public:
  /// Opens path for reading; error names the path and the reason.
  static Result<std::unique_ptr<FileSource>> open(const std::string& path);
  ~FileSource() override;
  FileSource(const FileSource&) = delete;
  FileSource& operator=(const FileSource&) = delete;
  uint64_t size() const override { return size_; }
  Status read(uint64_t offset, std::span<uint8_t> out) override;

 private:
  FileSource(int fd, uint64_t size) : fd_(fd), size_(size) {}
  int fd_;
  uint64_t size_;
};

}  // namespace stereoball::recorder
