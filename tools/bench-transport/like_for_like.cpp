#include "like_for_like.hpp"

namespace stereoball::bench_transport {

namespace {

std::vector<std::string> ddsperf_common(const DdsperfSetup& setup) {
  std::vector<std::string> args{"ddsperf", "-i", std::to_string(setup.domain)};
  if (setup.best_effort) args.push_back("-u");
  return args;
}

}  // namespace

std::vector<std::string> ddsperf_ping_args(const DdsperfSetup& setup) {
  auto args = ddsperf_common(setup);
  args.insert(args.end(), {"-D", std::to_string(setup.seconds), "-Qminmatch:1", "-Qinitwait:5",
                           "ping", "size", std::to_string(setup.sample_bytes), "waitset"});
  return args;
}

std::vector<std::string> ddsperf_pong_args(const DdsperfSetup& setup) {
  auto args = ddsperf_common(setup);
  args.insert(args.end(), {"-D", std::to_string(setup.seconds + 8), "pong", "waitset"});
  return args;
}

std::vector<std::string> with_cyclone_uri(const std::vector<std::string>& env,
                                          const std::string& uri) {
  const std::string key = "CYCLONEDDS_URI=";
  std::vector<std::string> out;
  for (const auto& e : env) {
    if (e.rfind(key, 0) != 0) out.push_back(e);
  }
  out.push_back(key + uri);
  return out;
}

std::vector<std::string> comparison_notes(const ComparisonFacts& f) {
  const std::string reliability = f.reliable ? "reliable" : "best-effort";
  std::vector<std::string> notes;
  notes.push_back(
      "same: two processes on this host, one ping outstanding (the next sent when the echo is "
      "back), waitset on both ends, " +
      reliability + " keep-last-1 volatile, Cyclone configuration " + f.config +
      ", half the round trip summarised per second");
  if (f.our_sample_bytes > 0 && f.our_sample_bytes == f.ddsperf_sample_bytes) {
    notes.push_back("same: " + std::to_string(f.our_sample_bytes) +
                    " B serialized per sample on both sides (ours: " +
                    std::to_string(f.our_pixel_bytes) + " B of pixels and " +
                    std::to_string(f.our_sample_bytes - f.our_pixel_bytes) + " B of header)");
  } else {
    notes.push_back("differs: sample size, ours " +
                    (f.our_sample_bytes > 0 ? std::to_string(f.our_sample_bytes) + " B serialized"
                                            : std::string("not measured")) +
                    ", ddsperf " + std::to_string(f.ddsperf_sample_bytes) + " B");
  }
  notes.push_back(
      "differs: ours is the typed StereoFrame (a struct with two octet sequences, written and "
      "taken through its generated descriptor), ddsperf its keyed octet sequence (KS)");
  notes.push_back(
      "differs: ours has two participants per process (one per direction, partitions ping and "
      "pong of one topic, sharing the process's domain and sockets), ddsperf one participant "
      "per process with a ping and a pong topic");
  notes.push_back(
      "differs: a ping not echoed: ours gives up after 100 ms, counts it lost and sends the "
      "next; ddsperf follows its own rule (its per-second counts show any loss)");
  return notes;
}

}  // namespace stereoball::bench_transport
