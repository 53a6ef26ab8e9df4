#include "simulator/core/range_check.hpp"

#include <cmath>
#include <sstream>

namespace stereoball::simulator {

Status check_range(const std::string& field, double v, double lo, double hi) {
  if (std::isfinite(v) && v >= lo && v <= hi) return {};
  std::ostringstream s;
  s << field << " = " << v << " is out of range [" << lo << ", " << hi << "]";
  return Error{s.str()};
}

}  // namespace stereoball::simulator
