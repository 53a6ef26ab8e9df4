#include "motion_controller/core/smooth_axis.hpp"

#include <algorithm>
#include <cmath>

namespace stereoball::motion_controller {
namespace {

// Velocity gained while the acceleration a steps down to zero by h per step of
// dt (a, h >= 0): dt * sum_k max(a - k h, 0).
double ramp_down_gain(double a, double h, double dt) {
  const double m = a / h;
  const double n = std::floor(m);
  return dt * h * (n * m - 0.5 * n * (n + 1.0));
}

// Velocity change of one step with acceleration a followed by a ramp to zero.
double travel(double a, double h, double dt) {
  const double ramp = ramp_down_gain(std::abs(a), h, dt);
  return a * dt + (a < 0.0 ? -ramp : ramp);
}

}  // namespace

double SmoothAxis::step(double target, double dt_s) {
  if (!(dt_s > 0.0)) return velocity_;
  target = std::clamp(target, limits_.min_velocity, limits_.max_velocity);
  // Work with a positive error; flip back at the end.
  const double error = target - velocity_;
  const double sign = error < 0.0 ? -1.0 : 1.0;
  const double e = std::abs(error);
  const double a = sign * accel_;
  const double h = limits_.max_jerk * dt_s;
  // Toward the target (+) slows the axis down when the velocity points away from it, and
  // away from the target (-) when it points toward it.
  const double toward = sign * velocity_;
  const double up_cap = toward < 0.0 ? limits_.max_brake : limits_.max_accel;
  const double down_cap = toward > 0.0 ? limits_.max_brake : limits_.max_accel;
  double lo = std::max(a - h, -down_cap);
  double hi = std::min(a + h, up_cap);
  // Braking harder than max_accel when the velocity passes zero: the acceleration ramps down
  // to the new bound at the jerk limit instead of jumping.
  if (lo > hi) {
    if (a > 0.0) {
      hi = lo;
    } else {
      lo = hi;
    }
  }
  // The largest acceleration this step from which a jerk-limited ramp to zero
  // still does not pass the target (travel() is increasing in a).
  double chosen = lo;
  const double exact = e / dt_s;  // lands on the target this step, then stops accelerating
  if (travel(hi, h, dt_s) <= e) {
    chosen = hi;
  } else if (exact >= lo && exact <= hi && exact <= h) {
    chosen = exact;
  } else if (travel(lo, h, dt_s) <= e) {
    double l = lo;
    double u = hi;
    for (int i = 0; i < 60; ++i) {
      const double mid = 0.5 * (l + u);
      (travel(mid, h, dt_s) <= e ? l : u) = mid;
    }
    chosen = l;
  }
  accel_ = sign * chosen;
  velocity_ = std::clamp(velocity_ + accel_ * dt_s, limits_.min_velocity, limits_.max_velocity);
  if (chosen == exact) velocity_ = target;  // no rounding residue
  return velocity_;
}

void SmoothAxis::reset() {
  velocity_ = 0.0;
  accel_ = 0.0;
}

}  // namespace stereoball::motion_controller
