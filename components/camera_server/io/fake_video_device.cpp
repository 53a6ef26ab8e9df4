#include "camera_server/io/fake_video_device.hpp"

#include <sys/eventfd.h>
#include <unistd.h>

#include <cerrno>

#include "camera_server/core/device_errors.hpp"

namespace stereoball::camera_server {
namespace {

void signal(int fd, uint64_t n) {
  if (fd >= 0 && n > 0) {
    [[maybe_unused]] const auto w = ::write(fd, &n, sizeof n);
  }
}

}  // namespace

void FakeCamera::push(FakeFrameScript f) {
  const std::lock_guard lock(mutex);
  script.push_back(std::move(f));
  signal(event_fd, 1);
}

size_t FakeCamera::queued() {
  const std::lock_guard lock(mutex);
  return script.size();
}

FakeVideoDevice::FakeVideoDevice(std::shared_ptr<FakeCamera> camera) : camera_(std::move(camera)) {}

FakeVideoDevice::~FakeVideoDevice() {
  close();
}

DeviceStatus FakeVideoDevice::open(const std::string& path) {
  path_ = path;
  ++camera_->opens;
  if (camera_->unplugged_opens_left > 0) {
    --camera_->unplugged_opens_left;
    return {ENOENT, errno_text(ENOENT, path, "open")};
  }
  if (camera_->open_errno != 0) {
    return {camera_->open_errno, errno_text(camera_->open_errno, path, "open")};
  }
  open_ = true;
  return {};
}

void FakeVideoDevice::close() {
  const std::lock_guard lock(camera_->mutex);
  if (event_fd_ >= 0) {
    ::close(event_fd_);
    if (camera_->event_fd == event_fd_) camera_->event_fd = -1;
  }
  event_fd_ = -1;
  open_ = false;
}

DeviceStatus FakeVideoDevice::query_caps(DeviceCaps& caps) {
  caps = camera_->caps;
  return {};
}

DeviceStatus FakeVideoDevice::enumerate_formats(std::vector<FormatOffer>& formats) {
  formats = camera_->formats;
  return {};
}

DeviceStatus FakeVideoDevice::set_format(const FormatChoice& choice, ActiveFormat& active) {
  camera_->formats_set.push_back(choice);
  active.fourcc = choice.fourcc;
  active.width_px = choice.width_px;
  active.height_px = choice.height_px;
  active.step_bytes = choice.fourcc == kFourccYuyv ? 2 * choice.width_px : 0;
  active.image_bytes = 2 * choice.width_px * choice.height_px;
  active_ = active;
  return {};
}

DeviceStatus FakeVideoDevice::set_control(const ControlSetting& control) {
  camera_->controls_set.push_back(control);
  return {};
}

DeviceStatus FakeVideoDevice::start_streaming(uint32_t) {
  if (!open_) return {EBADF, path_ + ": not open"};
  const std::lock_guard lock(camera_->mutex);
  event_fd_ = ::eventfd(0, EFD_SEMAPHORE | EFD_NONBLOCK | EFD_CLOEXEC);
  if (event_fd_ < 0) return {errno, errno_text(errno, path_, "eventfd")};
  camera_->event_fd = event_fd_;
  ++camera_->streams_started;
  signal(event_fd_, camera_->script.size());
  return {};
}

DeviceStatus FakeVideoDevice::dequeue(DequeuedFrame& frame) {
  const std::lock_guard lock(camera_->mutex);
  uint64_t token = 0;
  if (event_fd_ < 0 || ::read(event_fd_, &token, sizeof token) != sizeof token ||
      camera_->script.empty()) {
    return {EAGAIN, errno_text(EAGAIN, path_, "VIDIOC_DQBUF")};
  }
  current_ = std::move(camera_->script.front());
  camera_->script.pop_front();
  if (current_.err != 0) {
    if (current_.err == ENODEV) camera_->unplugged_opens_left = camera_->failed_opens_after_unplug;
    return {current_.err, errno_text(current_.err, path_, "VIDIOC_DQBUF")};
  }
  frame.data = current_.bytes.data();
  frame.bytes = current_.bytes.size();
  frame.stamp_ns = current_.stamp_ns;
  frame.index = 0;
  holding_ = true;
  return {};
}

DeviceStatus FakeVideoDevice::requeue(uint32_t) {
  holding_ = false;
  return {};
}

}  // namespace stereoball::camera_server
