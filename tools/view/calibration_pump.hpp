#pragma once
// The calibration mode of `stereoball view --calibrate`: its own stereo/frame reader and
// thread feed a calibrate_live::LiveStation (the same session as `stereoball calibrate live
// --terminal`); the page polls state_json() and its buttons call finish() and write(). Every
// pose, hint change, stall, failure and verdict also goes to the log.

#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

#include "common/dds/participant.hpp"
#include "live_station.hpp"

namespace stereoball::view {

class CalibrationPump {
 public:
  /// output: the file write() writes; timeout_ns: collecting ends then (the verdict of the
  /// poses taken, or the reason there is none).
  CalibrationPump(const dds::DomainParticipant& participant,
                  const calibrate_live::StationParams& params, std::string output,
                  int64_t timeout_ns);
  ~CalibrationPump();
  CalibrationPump(const CalibrationPump&) = delete;
  CalibrationPump& operator=(const CalibrationPump&) = delete;

  void start();
  void stop();
  /// The page's state (calibrate_live::LiveStation::state plus the output file).
  std::string state_json();
  /// Ends collecting now and judges the poses taken (the page's "calibrate now").
  void finish();
  /// Writes the file when the verdict passes; else (and on a write error) the reason, which
  /// the page shows. Thread-safe.
  Status write();
  /// finish() and write() on the pump's thread within 0.1 s (never blocks the caller: for
  /// the web server's thread).
  void request_finish() { finish_requested_ = true; }
  void request_write() { write_requested_ = true; }

 private:
  void run();
  void log_changes();  // under mutex_

  const dds::DomainParticipant& participant_;
  std::string output_;
  int64_t timeout_ns_;
  std::mutex mutex_;
  calibrate_live::LiveStation station_;  // under mutex_
  std::string last_message_;             // under mutex_: the last one logged
  bool verdict_logged_ = false;          // under mutex_
  std::atomic<bool> stop_{false}, finish_requested_{false}, write_requested_{false};
  std::thread thread_;
};

}  // namespace stereoball::view
