// How bench transport runs ddsperf beside its own ping-pong so that both measure the same thing
// (sample bytes, reliability, one ping outstanding, Cyclone configuration), and the lines that
// say in the output what is shared and what still differs.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace stereoball::bench_transport {

// One ddsperf ping-pong run.
struct DdsperfSetup {
  int domain = 0;           // ddsperf's domain (it has no partitions: one of its own)
  bool best_effort = true;  // -u
  size_t sample_bytes = 0;  // serialized payload without the 4-byte encapsulation header
  int seconds = 3;          // how long ping pings
};

// ddsperf's ping and pong command lines (program name first): ping waits for each echo before
// the next ping (no rate), both ends take in a waitset, as ours do.
std::vector<std::string> ddsperf_ping_args(const DdsperfSetup& setup);
std::vector<std::string> ddsperf_pong_args(const DdsperfSetup& setup);

// ENV ("NAME=VALUE" strings) with CYCLONEDDS_URI set to URI, replacing any earlier value.
std::vector<std::string> with_cyclone_uri(const std::vector<std::string>& env,
                                          const std::string& uri);

// What the comparison is made of, for the lines printed under the table.
struct ComparisonFacts {
  size_t our_sample_bytes = 0;      // ours, serialized payload as measured (0: not measured)
  size_t ddsperf_sample_bytes = 0;  // ddsperf's `size`
  size_t our_pixel_bytes = 0;       // of ours, the two eyes' pixels
  bool reliable = false;            // the reliability both sides use in the ratio
  std::string config;               // which Cyclone configuration both sides run under
};

// "same: ..." and "differs: ..." lines: every property of the two measurements, said plainly.
std::vector<std::string> comparison_notes(const ComparisonFacts& facts);

}  // namespace stereoball::bench_transport
