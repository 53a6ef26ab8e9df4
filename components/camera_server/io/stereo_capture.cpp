#include "camera_server/io/stereo_capture.hpp"

#include <poll.h>

#include <cerrno>
#include <cstdio>

#include "camera_server/core/device_errors.hpp"

namespace stereoball::camera_server {
namespace {

constexpr std::array<Eye, 2> kEyes{Eye::kLeft, Eye::kRight};

BackoffParams backoff_params(const CameraServerParams& p) {
  return BackoffParams{p.reopen_initial_s, p.reopen_max_s, p.reopen_factor};
}

std::string seconds_text(int64_t ns) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f s", static_cast<double>(ns) * 1e-9);
  return buf;
}

}  // namespace

StereoCapture::StereoCapture(const CameraServerParams& params, DeviceFactory factory)
    : params_(params),
      factory_(std::move(factory)),
      eyes_{EyeState{nullptr,
                     camera_config(params, params.left_device),
                     {},
                     ReopenBackoff(backoff_params(params))},
            EyeState{nullptr,
                     camera_config(params, params.right_device),
                     {},
                     ReopenBackoff(backoff_params(params))}},
      pairer_(PairerParams{params.effective_skew_ns(), 4}) {
  for (Eye e : kEyes) state(e).health.path = state(e).config.path;
}

DeviceStatus StereoCapture::open_eye(Eye eye) {
  EyeState& s = state(eye);
  if (!s.device) s.device = factory_(eye);
  OpenedCamera opened;
  DeviceStatus st = open_camera(*s.device, s.config, opened);
  if (!st.ok()) return st;
  s.health.streaming = true;
  s.health.format = opened.format;
  s.last_frame_ns = -1;
  for (auto& w : opened.warnings) log_.push_back(std::string(eye_name(eye)) + " camera: " + w);
  return st;
}

DeviceStatus StereoCapture::start() {
  if (auto st = check_distinct_devices(params_.left_device, params_.right_device); !st) {
    return {EINVAL, st.error()};
  }
  for (Eye e : kEyes) {
    DeviceStatus st = open_eye(e);
    if (!st.ok()) {
      for (Eye o : kEyes) {
        if (state(o).device) state(o).device->close();
        state(o).health.streaming = false;
      }
      return {st.err, std::string(eye_name(e)) + " camera: " + st.message};
    }
  }
  return {};
}

void StereoCapture::lose(Eye eye, const DeviceStatus& status, int64_t now_ns) {
  EyeState& s = state(eye);
  s.device->close();
  s.health.streaming = false;
  ++s.health.errors;
  s.health.last_error = status.message;
  pairer_.flush();
  const int64_t next = s.backoff.on_failure(now_ns);
  log_.push_back(std::string(eye_name(eye)) + " camera lost: " + status.message +
                 "; reopening in " + seconds_text(next - now_ns));
}

void StereoCapture::try_reopen(Eye eye, int64_t now_ns) {
  EyeState& s = state(eye);
  if (s.health.streaming || !s.backoff.due(now_ns)) return;
  const DeviceStatus st = open_eye(eye);
  if (st.ok()) {
    log_.push_back(std::string(eye_name(eye)) + " camera " + s.config.path + " reopened after " +
                   std::to_string(s.backoff.failures()) + " attempt(s)");
    s.backoff.on_success();
    ++s.health.reopens;
    return;
  }
  s.health.last_error = st.message;
  const int64_t next = s.backoff.on_failure(now_ns);
  log_.push_back(std::string(eye_name(eye)) + " camera reopen failed: " + st.message +
                 "; next attempt in " + seconds_text(next - now_ns));
}

void StereoCapture::drain(Eye eye, int64_t now_ns, std::vector<RawStereoPair>& pairs) {
  EyeState& s = state(eye);
  // Bounded: never more than the driver's queue per wake-up, so one eye cannot starve the other.
  for (uint32_t i = 0; i < params_.buffer_count && s.health.streaming; ++i) {
    DequeuedFrame f;
    const DeviceStatus st = s.device->dequeue(f);
    if (!st.ok()) {
      if (classify_errno(st.err) != ErrorClass::kRetry) lose(eye, st, now_ns);
      return;
    }
    const ActiveFormat& fmt = s.health.format;
    const size_t min_bytes = fmt.step_bytes > 0 ? size_t{fmt.step_bytes} * fmt.height_px : 1;
    if (f.corrupted || f.bytes < min_bytes) {
      ++s.health.corrupted;
      s.device->requeue(f.index);
      continue;
    }
    ++s.health.frames;
    s.last_frame_ns = now_ns;
    EyeFrame<RawImage> frame{eye, f.stamp_ns, {}};
    frame.payload.bytes.assign(f.data, f.data + f.bytes);
    frame.payload.fourcc = fmt.fourcc;
    frame.payload.width_px = fmt.width_px;
    frame.payload.height_px = fmt.height_px;
    frame.payload.step_bytes = fmt.step_bytes;
    frame.payload.sequence = f.sequence;
    if (auto q = s.device->requeue(f.index); !q.ok()) {
      lose(eye, q, now_ns);
      return;
    }
    if (auto r = pairer_.step(std::move(frame)); r.pair) pairs.push_back(std::move(*r.pair));
  }
}

// A camera can stop delivering without any error (USB bandwidth, power, firmware): after
// stall_timeout_s of silence it is treated like an unplug and reopened.
void StereoCapture::check_stall(Eye eye, int64_t now_ns) {
  EyeState& s = state(eye);
  if (!s.health.streaming) return;
  if (s.last_frame_ns < 0) {
    s.last_frame_ns = now_ns;
    return;
  }
  const auto stall_ns = static_cast<int64_t>(params_.stall_timeout_s * 1e9);
  if (now_ns - s.last_frame_ns > stall_ns) {
    lose(eye,
         {ETIMEDOUT, s.config.path + ": no frame for " + seconds_text(now_ns - s.last_frame_ns) +
                         " (camera stalled: USB bandwidth, power or cable?)"},
         now_ns);
  }
}

std::vector<RawStereoPair> StereoCapture::poll_once(int timeout_ms, int64_t now_ns) {
  std::vector<RawStereoPair> pairs;
  for (Eye e : kEyes) try_reopen(e, now_ns);
  for (Eye e : kEyes) check_stall(e, now_ns);
  std::array<pollfd, 2> fds{};
  std::array<Eye, 2> which{};
  nfds_t n = 0;
  for (Eye e : kEyes) {
    if (!state(e).health.streaming) continue;
    fds[n] = pollfd{state(e).device->poll_fd(), POLLIN, 0};
    which[n++] = e;
  }
  const int ready = ::poll(fds.data(), n, timeout_ms);
  if (ready <= 0) return pairs;  // timeout or EINTR: the caller loops
  for (nfds_t i = 0; i < n; ++i) {
    // POLLERR/POLLHUP after an unplug: dequeue reports the errno that explains it.
    if (fds[i].revents != 0) drain(which[i], now_ns, pairs);
  }
  return pairs;
}

std::vector<std::string> StereoCapture::take_log() {
  std::vector<std::string> out;
  out.swap(log_);
  return out;
}

CaptureHealth StereoCapture::health() const {
  CaptureHealth h;
  h.eyes[0] = eyes_[0].health;
  h.eyes[1] = eyes_[1].health;
  h.pairing = pairer_.stats();
  return h;
}

bool StereoCapture::healthy() const {
  return eyes_[0].health.streaming && eyes_[1].health.streaming;
}

}  // namespace stereoball::camera_server
