#include "recorder/core/selection.hpp"

#include <algorithm>
#include <cmath>

namespace stereoball::recorder {
namespace {

std::string known_list(const std::vector<std::string>& available) {
  std::string out;
  for (const auto& a : available) out += (out.empty() ? "" : ", ") + a;
  return out;
}

bool contains(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

}  // namespace

Result<std::vector<std::string>> select_topics(const std::vector<std::string>& available,
                                               const std::vector<std::string>& requested, bool all,
                                               const std::vector<std::string>& exclude) {
  if (all && !requested.empty()) return Error{"give either --all or topic names, not both"};
  if (!all && requested.empty()) return Error{"no topics given (name topics or use --all)"};
  for (const auto& list : {requested, exclude}) {
    for (const auto& t : list) {
      if (!contains(available, t)) {
        return Error{"unknown topic '" + t + "' (known: " + known_list(available) + ")"};
      }
    }
  }
  std::vector<std::string> out;
  for (const auto& t : all ? available : requested) {
    if (!contains(exclude, t) && !contains(out, t)) out.push_back(t);
  }
  if (out.empty()) return Error{"every selected topic is excluded; nothing to record"};
  return out;
}

Status PlaybackParams::validate() const {
  if (!(rate >= 0.01 && rate <= 100.0)) {
    return Error{"rate must be in [0.01, 100], got " + std::to_string(rate)};
  }
  if (!(start_offset_s >= 0.0) || !std::isfinite(start_offset_s)) {
    return Error{"start_offset_s must be >= 0 seconds, got " + std::to_string(start_offset_s)};
  }
  return {};
}

int64_t PlaybackSchedule::due_ns(uint64_t log_ns) const {
  // Messages logged before the first one (out of order) are due immediately.
  if (log_ns <= first_log_ns_) return start_ns_;
  const double elapsed = static_cast<double>(log_ns - first_log_ns_) / rate_;
  return start_ns_ + static_cast<int64_t>(std::llround(elapsed));
}

}  // namespace stereoball::recorder
