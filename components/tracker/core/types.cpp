#include "tracker/core/types.hpp"

namespace stereoball::tracker {

bool is_accepted(Verdict v) {
  return v == Verdict::kStartupAccepted || v == Verdict::kBlockMatchAccepted ||
         v == Verdict::kStatisticsAccepted;
}

std::string_view to_string(TrackState s) {
  switch (s) {
    case TrackState::kIdle:
      return "idle";
    case TrackState::kFollowing:
      return "following";
    case TrackState::kSearching:
      return "searching";
  }
  return "unknown";
}

std::string_view to_string(Side s) {
  switch (s) {
    case Side::kLeft:
      return "left";
    case Side::kRight:
      return "right";
    case Side::kUnknown:
      break;
  }
  return "unknown";
}

std::string_view to_string(Verdict v) {
  switch (v) {
    case Verdict::kNoDetection:
      return "no_detection";
    case Verdict::kStartupCollecting:
      return "startup_collecting";
    case Verdict::kStartupInconsistent:
      return "startup_inconsistent";
    case Verdict::kStartupAccepted:
      return "startup_accepted";
    case Verdict::kBlockMatchAccepted:
      return "block_match_accepted";
    case Verdict::kStatisticsAccepted:
      return "statistics_accepted";
    case Verdict::kRejected:
      return "rejected";
  }
  return "unknown";
}

}  // namespace stereoball::tracker
