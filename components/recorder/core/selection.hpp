#pragma once
// Pure helpers for `stereoball record` and `stereoball play`: which topics to use, and when
// a recorded message is due during playback.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/util/result.hpp"

namespace stereoball::recorder {

/// Topics to record: all of available when all is set, else requested (each must exist),
/// minus exclude (each must exist). Error names the unknown topic and lists the known ones.
Result<std::vector<std::string>> select_topics(const std::vector<std::string>& available,
                                               const std::vector<std::string>& requested, bool all,
                                               const std::vector<std::string>& exclude);

/// Playback settings.
struct PlaybackParams {
  double rate = 1.0;            ///< time scale: 2 = twice as fast
  double start_offset_s = 0.0;  ///< skip this much of the recording's start, seconds
  bool loop = false;            ///< start over at the end
  /// Success, or an error naming the bad field and its allowed range.
  Status validate() const;
};

/// When each message of a recording is due: log times are mapped to a wall clock that
/// starts at start_ns, scaled by 1/rate.
class PlaybackSchedule {
 public:
  /// first_log_ns: log time played at start_ns (ns); rate as in PlaybackParams.
  PlaybackSchedule(uint64_t first_log_ns, int64_t start_ns, double rate)
      : first_log_ns_(first_log_ns), start_ns_(start_ns), rate_(rate) {}
  /// Clock time (ns, same clock as start_ns) at which a message logged at log_ns is due.
  int64_t due_ns(uint64_t log_ns) const;

 private:
  uint64_t first_log_ns_;
  int64_t start_ns_;
  double rate_;
};

}  // namespace stereoball::recorder
