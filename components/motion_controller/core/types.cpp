#include "motion_controller/core/types.hpp"

namespace stereoball::motion_controller {

std::string_view to_string(Mode m) {
  switch (m) {
    case Mode::kWaiting:
      return "waiting";
    case Mode::kIdle:
      return "idle";
    case Mode::kFollowing:
      return "following";
    case Mode::kHolding:
      return "holding";
    case Mode::kSearching:
      return "searching";
    case Mode::kSearchGaveUp:
      return "search_gave_up";
    case Mode::kStale:
      return "stale";
    case Mode::kEmergencyStop:
      return "emergency_stop";
  }
  return "unknown";
}

}  // namespace stereoball::motion_controller
