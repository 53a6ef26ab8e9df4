#include "motion_controller/core/types.hpp"

#include <cmath>

namespace stereoball::motion_controller {

PolarRates polar_rates(double x_m, double z_m, double vx_mps, double vz_mps) {
  const double r2 = x_m * x_m + z_m * z_m;
  if (!(r2 > 1e-6)) return {};  // also catches NaN
  PolarRates out;
  out.bearing_radps = (z_m * vx_mps - x_m * vz_mps) / r2;
  out.range_mps = (x_m * vx_mps + z_m * vz_mps) / std::sqrt(r2);
  if (!std::isfinite(out.bearing_radps) || !std::isfinite(out.range_mps)) return {};
  return out;
}

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

std::string_view to_string(StampCheck c) {
  switch (c) {
    case StampCheck::kNew:
      return "new";
    case StampCheck::kRepeated:
      return "repeated (same frame as the last track)";
    case StampCheck::kZero:
      return "zero (never set)";
    case StampCheck::kFuture:
      return "in the future";
    case StampCheck::kBackwards:
      return "going backwards";
  }
  return "unknown";
}

}  // namespace stereoball::motion_controller
