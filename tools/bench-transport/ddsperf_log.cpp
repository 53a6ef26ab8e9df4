#include "ddsperf_log.hpp"

#include <regex>
#include <sstream>

namespace stereoball::bench_transport {

DdsperfSeconds parse_ddsperf_ping_log(const std::string& log) {
  static const std::regex kLine(
      R"(size (\d+) mean [\d.]+us min [\d.]+us 50% ([\d.]+)us 90% [\d.]+us 99% ([\d.]+)us max [\d.]+us cnt (\d+))");
  DdsperfSeconds out;
  std::istringstream in(log);
  bool first = true;
  for (std::string line; std::getline(in, line);) {
    std::smatch m;
    if (!std::regex_search(line, m, kLine)) continue;
    if (first) {  // the first second includes discovery and warm-up
      first = false;
      continue;
    }
    const size_t n = std::stoul(m[4]);
    out.count += n;
    ++out.seconds;
    if (n < kMinSamplesPerSecond) {
      ++out.sparse_seconds;
      continue;
    }
    out.medians_us.push_back(std::stod(m[2]));
    out.p99s_us.push_back(std::stod(m[3]));
  }
  return out;
}

}  // namespace stereoball::bench_transport
