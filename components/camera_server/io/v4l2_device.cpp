#include "camera_server/io/v4l2_device.hpp"

#include <fcntl.h>
#include <linux/videodev2.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <ctime>

#include "camera_server/core/device_errors.hpp"
#include "common/util/clock_stamp.hpp"

namespace stereoball::camera_server {
namespace {

// ioctl that restarts when a signal interrupts it.
int xioctl(int fd, unsigned long request, void* arg) {
  int r;
  do {
    r = ::ioctl(fd, request, arg);
  } while (r == -1 && errno == EINTR);
  return r;
}

int64_t clock_ns(clockid_t id) {
  timespec ts{};
  clock_gettime(id, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

std::string text(const __u8* s, size_t n) {
  return std::string(reinterpret_cast<const char*>(s),
                     strnlen(reinterpret_cast<const char*>(s), n));
}

// Buffer stamps are CLOCK_MONOTONIC on modern drivers; messages carry CLOCK_REALTIME.
int64_t to_epoch_ns(const v4l2_buffer& b) {
  const int64_t t = static_cast<int64_t>(b.timestamp.tv_sec) * 1'000'000'000 +
                    static_cast<int64_t>(b.timestamp.tv_usec) * 1000;
  const uint32_t kind = b.flags & V4L2_BUF_FLAG_TIMESTAMP_MASK;
  if (kind == V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC && t > 0) {
    return monotonic_to_epoch_ns(t, clock_ns(CLOCK_MONOTONIC), clock_ns(CLOCK_REALTIME));
  }
  return clock_ns(CLOCK_REALTIME);
}

}  // namespace

V4l2Device::~V4l2Device() {
  close();
}

DeviceStatus V4l2Device::error(const char* operation) const {
  const int err = errno;
  return {err, errno_text(err, path_, operation)};
}

DeviceStatus V4l2Device::open(const std::string& path) {
  close();
  path_ = path;
  struct stat st {};
  if (::stat(path.c_str(), &st) == -1) return error("open");
  if (!S_ISCHR(st.st_mode)) {
    return {ENOTTY, path + ": not a device node (expected a character device like /dev/video0)"};
  }
  fd_ = ::open(path.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (fd_ == -1) return error("open");
  return {};
}

void V4l2Device::close() {
  if (fd_ == -1) return;
  if (streaming_) {
    v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    xioctl(fd_, VIDIOC_STREAMOFF, &type);  // may fail after unplug; nothing to do about it
    streaming_ = false;
  }
  release_buffers();
  ::close(fd_);
  fd_ = -1;
}

void V4l2Device::release_buffers() {
  for (auto& b : buffers_) {
    if (b.start != nullptr && b.start != MAP_FAILED) ::munmap(b.start, b.length);
  }
  buffers_.clear();
  if (fd_ != -1) {
    v4l2_requestbuffers req{};
    req.count = 0;
    req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    req.memory = V4L2_MEMORY_MMAP;
    xioctl(fd_, VIDIOC_REQBUFS, &req);
  }
}

DeviceStatus V4l2Device::query_caps(DeviceCaps& caps) {
  v4l2_capability cap{};
  if (xioctl(fd_, VIDIOC_QUERYCAP, &cap) == -1) {
    if (errno == ENOTTY || errno == EINVAL) {
      return {errno, path_ + ": not a V4L2 video device (VIDIOC_QUERYCAP unsupported)"};
    }
    return error("VIDIOC_QUERYCAP");
  }
  // device_caps describes this node; capabilities the whole physical device.
  const uint32_t c = (cap.capabilities & V4L2_CAP_DEVICE_CAPS) ? cap.device_caps : cap.capabilities;
  caps.driver = text(cap.driver, sizeof cap.driver);
  caps.card = text(cap.card, sizeof cap.card);
  caps.bus_info = text(cap.bus_info, sizeof cap.bus_info);
  caps.video_capture = (c & V4L2_CAP_VIDEO_CAPTURE) != 0;
  caps.streaming = (c & V4L2_CAP_STREAMING) != 0;
  return {};
}

std::vector<double> V4l2Device::enumerate_rates(uint32_t fourcc, uint32_t w, uint32_t h) {
  std::vector<double> rates;
  v4l2_frmivalenum iv{};
  iv.pixel_format = fourcc;
  iv.width = w;
  iv.height = h;
  for (iv.index = 0; xioctl(fd_, VIDIOC_ENUM_FRAMEINTERVALS, &iv) == 0; ++iv.index) {
    if (iv.type != V4L2_FRMIVAL_TYPE_DISCRETE) break;  // continuous: any rate, report none
    if (iv.discrete.numerator > 0) {
      const double r = static_cast<double>(iv.discrete.denominator) / iv.discrete.numerator;
      rates.push_back(std::round(r * 100.0) / 100.0);
    }
  }
  return rates;
}

void V4l2Device::enumerate_sizes(uint32_t fourcc, FormatOffer& offer) {
  v4l2_frmsizeenum fs{};
  fs.pixel_format = fourcc;
  for (fs.index = 0; xioctl(fd_, VIDIOC_ENUM_FRAMESIZES, &fs) == 0; ++fs.index) {
    SizeOffer s;
    if (fs.type == V4L2_FRMSIZE_TYPE_DISCRETE) {
      s.min_width_px = s.max_width_px = fs.discrete.width;
      s.min_height_px = s.max_height_px = fs.discrete.height;
      s.rates_hz = enumerate_rates(fourcc, fs.discrete.width, fs.discrete.height);
      offer.sizes.push_back(std::move(s));
      continue;
    }
    s.min_width_px = fs.stepwise.min_width;
    s.max_width_px = fs.stepwise.max_width;
    s.step_width_px = fs.stepwise.step_width;
    s.min_height_px = fs.stepwise.min_height;
    s.max_height_px = fs.stepwise.max_height;
    s.step_height_px = fs.stepwise.step_height;
    offer.sizes.push_back(std::move(s));
    break;  // stepwise/continuous has a single entry
  }
}

DeviceStatus V4l2Device::enumerate_formats(std::vector<FormatOffer>& formats) {
  formats.clear();
  v4l2_fmtdesc fd{};
  fd.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  for (fd.index = 0;; ++fd.index) {
    if (xioctl(fd_, VIDIOC_ENUM_FMT, &fd) == -1) {
      if (errno == EINVAL) break;  // end of the list
      return error("VIDIOC_ENUM_FMT");
    }
    FormatOffer offer;
    offer.fourcc = fd.pixelformat;
    offer.description = text(fd.description, sizeof fd.description);
    enumerate_sizes(fd.pixelformat, offer);
    formats.push_back(std::move(offer));
  }
  return {};
}

DeviceStatus V4l2Device::set_format(const FormatChoice& choice, ActiveFormat& active) {
  v4l2_format fmt{};
  fmt.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  fmt.fmt.pix.width = choice.width_px;
  fmt.fmt.pix.height = choice.height_px;
  fmt.fmt.pix.pixelformat = choice.fourcc;
  fmt.fmt.pix.field = V4L2_FIELD_ANY;
  if (xioctl(fd_, VIDIOC_S_FMT, &fmt) == -1) return error("VIDIOC_S_FMT");
  // Drivers silently substitute what they can do; a different result is a configuration error.
  if (fmt.fmt.pix.pixelformat != choice.fourcc || fmt.fmt.pix.width != choice.width_px ||
      fmt.fmt.pix.height != choice.height_px) {
    return {EINVAL, path_ + ": driver set " + fourcc_text(fmt.fmt.pix.pixelformat) + " " +
                        std::to_string(fmt.fmt.pix.width) + "x" +
                        std::to_string(fmt.fmt.pix.height) + " instead of " +
                        fourcc_text(choice.fourcc) + " " + std::to_string(choice.width_px) + "x" +
                        std::to_string(choice.height_px)};
  }
  active.fourcc = fmt.fmt.pix.pixelformat;
  active.width_px = fmt.fmt.pix.width;
  active.height_px = fmt.fmt.pix.height;
  active.step_bytes = fmt.fmt.pix.bytesperline;
  active.image_bytes = fmt.fmt.pix.sizeimage;

  v4l2_streamparm parm{};
  parm.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  if (xioctl(fd_, VIDIOC_G_PARM, &parm) == 0 &&
      (parm.parm.capture.capability & V4L2_CAP_TIMEPERFRAME) != 0) {
    parm.parm.capture.timeperframe.numerator = 1000;
    parm.parm.capture.timeperframe.denominator =
        static_cast<uint32_t>(std::lround(choice.rate_hz * 1000.0));
    if (xioctl(fd_, VIDIOC_S_PARM, &parm) == -1) return error("VIDIOC_S_PARM (frame rate)");
  }
  return {};
}

DeviceStatus V4l2Device::set_control(const ControlSetting& control) {
  v4l2_control c{};
  c.id = control.id;
  c.value = control.value;
  if (xioctl(fd_, VIDIOC_S_CTRL, &c) == -1) {
    const int err = errno;
    if (err == EINVAL || err == ERANGE) {
      return {err, path_ + ": camera does not support control " + control.name + " = " +
                       std::to_string(control.value)};
    }
    return {err, errno_text(err, path_, "VIDIOC_S_CTRL " + control.name)};
  }
  return {};
}

DeviceStatus V4l2Device::start_streaming(uint32_t buffer_count) {
  v4l2_requestbuffers req{};
  req.count = buffer_count;
  req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  req.memory = V4L2_MEMORY_MMAP;
  if (xioctl(fd_, VIDIOC_REQBUFS, &req) == -1) return error("VIDIOC_REQBUFS");
  if (req.count < 2) return {ENOMEM, path_ + ": driver granted fewer than 2 capture buffers"};
  buffers_.resize(req.count);
  for (uint32_t i = 0; i < req.count; ++i) {
    v4l2_buffer b{};
    b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    b.memory = V4L2_MEMORY_MMAP;
    b.index = i;
    if (xioctl(fd_, VIDIOC_QUERYBUF, &b) == -1) return error("VIDIOC_QUERYBUF");
    buffers_[i].length = b.length;
    buffers_[i].start =
        ::mmap(nullptr, b.length, PROT_READ | PROT_WRITE, MAP_SHARED, fd_, b.m.offset);
    if (buffers_[i].start == MAP_FAILED) return error("mmap");
    if (xioctl(fd_, VIDIOC_QBUF, &b) == -1) return error("VIDIOC_QBUF");
  }
  v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  if (xioctl(fd_, VIDIOC_STREAMON, &type) == -1) return error("VIDIOC_STREAMON");
  streaming_ = true;
  return {};
}

DeviceStatus V4l2Device::dequeue(DequeuedFrame& frame) {
  v4l2_buffer b{};
  b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  b.memory = V4L2_MEMORY_MMAP;
  if (xioctl(fd_, VIDIOC_DQBUF, &b) == -1) return error("VIDIOC_DQBUF");
  if (b.index >= buffers_.size()) return {EIO, path_ + ": driver returned an unknown buffer index"};
  frame.data = static_cast<const uint8_t*>(buffers_[b.index].start);
  frame.bytes = b.bytesused;
  frame.stamp_ns = to_epoch_ns(b);
  frame.sequence = b.sequence;
  frame.index = b.index;
  frame.corrupted = (b.flags & V4L2_BUF_FLAG_ERROR) != 0;
  return {};
}

DeviceStatus V4l2Device::requeue(uint32_t index) {
  v4l2_buffer b{};
  b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  b.memory = V4L2_MEMORY_MMAP;
  b.index = index;
  if (xioctl(fd_, VIDIOC_QBUF, &b) == -1) return error("VIDIOC_QBUF");
  return {};
}

}  // namespace stereoball::camera_server
