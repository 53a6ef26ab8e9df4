#pragma once
// The simulator's one range rule for scenario and scene fields: finite and within [lo, hi].

#include <string>

#include "common/util/result.hpp"

namespace stereoball::simulator {

/// Ok when v is finite and in [lo, hi]; otherwise "FIELD = v is out of range [lo, hi]".
Status check_range(const std::string& field, double v, double lo, double hi);

}  // namespace stereoball::simulator
