#include "recorder/io/file_io.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace stereoball::recorder {

Result<std::unique_ptr<FileSink>> FileSink::create(const std::string& path, bool sync_on_flush) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) {
    return Error{"cannot create '" + path + "': " + std::strerror(errno)};
  }
  return std::unique_ptr<FileSink>(new FileSink(fd, path, sync_on_flush));
}

FileSink::~FileSink() {
  ::close(fd_);
}

Status FileSink::write(std::span<const uint8_t> bytes) {
  const uint8_t* p = bytes.data();
  size_t left = bytes.size();
  while (left > 0) {
    const ssize_t n = ::write(fd_, p, left);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0)
      return Error{"'" + path_ + "': " + (n < 0 ? std::strerror(errno) : "wrote 0 bytes")};
    p += n;
    left -= static_cast<size_t>(n);
  }
  return {};
}

Status FileSink::flush() {
  if (sync_on_flush_ && ::fdatasync(fd_) != 0) {
    return Error{"'" + path_ + "': fdatasync: " + std::strerror(errno)};
  }
  return {};
}

Status FileSink::sync() {
  if (::fdatasync(fd_) != 0) return Error{"'" + path_ + "': fdatasync: " + std::strerror(errno)};
  return {};
}

Result<std::unique_ptr<FileSpill>> FileSpill::create(const std::string& dir) {
  const std::string where = dir.empty() ? "." : dir;
  int fd = ::open(where.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0600);
  if (fd < 0 && (errno == EOPNOTSUPP || errno == EISDIR || errno == EINVAL)) {
    // A file system without O_TMPFILE: a named file, unlinked at once.
    std::string name = where + "/.stereoball-spill-XXXXXX";
    fd = ::mkostemp(name.data(), O_CLOEXEC);
    if (fd >= 0) ::unlink(name.c_str());
  }
  if (fd < 0) {
    return Error{"cannot create a temporary file in '" + where + "': " + std::strerror(errno)};
  }
  return std::unique_ptr<FileSpill>(new FileSpill(fd, where));
}

FileSpill::~FileSpill() {
  ::close(fd_);
}

Status FileSpill::write(std::span<const uint8_t> bytes) {
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n =
        ::pwrite(fd_, bytes.data() + done, bytes.size() - done, static_cast<off_t>(size_ + done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      return Error{"temporary file in '" + dir_ +
                   "': " + (n < 0 ? std::strerror(errno) : "wrote 0 bytes")};
    }
    done += static_cast<size_t>(n);
  }
  size_ += done;
  return {};
}

Status FileSpill::read(uint64_t offset, std::span<uint8_t> out) {
  if (offset > size_ || out.size() > size_ - offset) {
    return Error{"temporary file in '" + dir_ + "': read past its " + std::to_string(size_) +
                 " bytes"};
  }
  size_t done = 0;
  while (done < out.size()) {
    const ssize_t n =
        ::pread(fd_, out.data() + done, out.size() - done, static_cast<off_t>(offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      return Error{"temporary file in '" + dir_ +
                   "': " + (n < 0 ? std::strerror(errno) : "unexpected end")};
    }
    done += static_cast<size_t>(n);
  }
  return {};
}

Result<std::unique_ptr<FileSource>> FileSource::open(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    return Error{"cannot open '" + path + "': " + std::strerror(errno)};
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    return Error{"'" + path + "' is not a regular file"};
  }
  return std::unique_ptr<FileSource>(new FileSource(fd, static_cast<uint64_t>(st.st_size)));
}

FileSource::~FileSource() {
  ::close(fd_);
}

Status FileSource::read(uint64_t offset, std::span<uint8_t> out) {
  size_t done = 0;
  while (done < out.size()) {
    const ssize_t n =
        ::pread(fd_, out.data() + done, out.size() - done, static_cast<off_t>(offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return Error{std::string("read failed: ") + std::strerror(errno)};
    if (n == 0) return Error{"unexpected end of file at offset " + std::to_string(offset + done)};
    done += static_cast<size_t>(n);
  }
  return {};
}

}  // namespace stereoball::recorder
