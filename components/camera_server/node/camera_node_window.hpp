#pragma once
// The figures of stereoball bench camera-node over its measured window: the node's CPU divided
// by the frames it actually published in that window (from the frames' seq), not by the rate
// it was asked for, so a node that falls behind is not credited with frames it never sent.

#include <cstdint>

#include <string>

#include "common/util/result.hpp"

namespace stereoball::camera_server {

/// One end of the measured window, read in the subscriber.
struct WindowMark {
  int64_t now_ns = 0;     ///< monotonic time of the reading, ns
  double cpu_s = 0.0;     ///< the node's utime + stime, s
  uint64_t last_seq = 0;  ///< seq of the newest frame received by then
};

/// The window's figures.
struct WindowFigures {
  double wall_s = 0.0;            ///< window length, s
  uint64_t published = 0;         ///< frames the node published in it (seq advance)
  double published_hz = 0.0;      ///< published / wall_s, Hz
  double cpu_percent = 0.0;       ///< node CPU, % of one core
  double cpu_us_per_frame = 0.0;  ///< node CPU per published frame, us
};

/// Figures between START and END, or an error when the window is empty or no frame was
/// published in it (seq did not advance).
inline Result<WindowFigures> window_figures(const WindowMark& start, const WindowMark& end) {
  if (end.now_ns <= start.now_ns) return Error{"the measured window is empty"};
  if (end.last_seq <= start.last_seq)
    return Error{"no frame was published in the measured window (seq stayed at " +
                 std::to_string(start.last_seq) + ")"};
  WindowFigures f;
  f.wall_s = static_cast<double>(end.now_ns - start.now_ns) * 1e-9;
  f.published = end.last_seq - start.last_seq;
  f.published_hz = static_cast<double>(f.published) / f.wall_s;
  const double cpu_s = end.cpu_s - start.cpu_s;
  f.cpu_percent = 100.0 * cpu_s / f.wall_s;
  f.cpu_us_per_frame = cpu_s * 1e6 / static_cast<double>(f.published);
  return f;
}

}  // namespace stereoball::camera_server
