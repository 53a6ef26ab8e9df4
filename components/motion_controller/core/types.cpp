#include "motion_controller/core/types.hpp"

#include <cmath>

#include "common/util/enum_names.hpp"

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

namespace {

constexpr util::EnumName<Mode> kModeNames[] = {
    {Mode::kWaiting, "waiting"},     {Mode::kIdle, "idle"},
    {Mode::kFollowing, "following"}, {Mode::kHolding, "holding"},
    {Mode::kSearching, "searching"}, {Mode::kSearchGaveUp, "search_gave_up"},
    {Mode::kStale, "stale"},         {Mode::kEmergencyStop, "emergency_stop"},
};

constexpr util::EnumName<StampCheck> kStampCheckNames[] = {
    {StampCheck::kNew, "new"},
    {StampCheck::kRepeated, "repeated (same frame as the last track)"},
    {StampCheck::kZero, "zero (never set)"},
    {StampCheck::kFuture, "in the future"},
    {StampCheck::kBackwards, "going backwards"},
};

}  // namespace

std::string_view to_string(Mode m) {
  return util::name_of(kModeNames, m);
}

std::string_view to_string(StampCheck c) {
  return util::name_of(kStampCheckNames, c);
}

}  // namespace stereoball::motion_controller
