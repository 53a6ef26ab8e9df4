#pragma once
// What the viewer watches in the benchmark: the demo (simulator, ball detector, tracker,
// motion controller as separate processes) or a synthetic stereo stream published from this
// process; and a count of the frames that actually flow.

#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "frame_count.hpp"
#include "processes.hpp"

namespace stereoball::bench {

class Source {
 public:
  virtual ~Source() = default;
  /// The partition (pattern) the viewer must use to see this source.
  virtual std::string partition() const = 0;
  /// The processes of the robot side (their CPU is what the viewer must not raise).
  virtual std::vector<pid_t> robot_processes() const = 0;
  virtual std::string describe() const = 0;
};

/// `stereoball demo` on one scenario for as long as the benchmark runs.
std::unique_ptr<Source> start_demo(int domain, const std::string& scenario,
                                   const std::string& work_dir, std::string& error);

/// A synthetic width x height stereo pair (bgr8, or JPEG as from JPEG cameras) with
/// detections, tracks and ground truth at rate_hz, published from a thread of this process.
std::unique_ptr<Source> start_synthetic(int domain, int width, int height, double rate_hz,
                                        bool jpeg);

/// Stereo frames per second that flow, from the ground truth's frame numbers (a small topic:
/// reading it costs the camera nothing worth mentioning).
class FrameRate {
 public:
  FrameRate(int domain, const std::string& partition);
  ~FrameRate();
  /// Marks the start of a measurement.
  void restart();
  /// Frames per second since restart() (from the first frame after it if none had come yet).
  double rate_hz() const;

 private:
  std::atomic<bool> stop_{false};
  mutable std::mutex mutex_;
  FrameCount count_;  // guarded by mutex_
  std::thread thread_;
};

}  // namespace stereoball::bench
