#include "chaos_plan.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include "common/util/enum_names.hpp"

namespace stereoball::bench_chaos {
namespace {

constexpr util::EnumName<FaultKind> kFaultNames[] = {
    {FaultKind::kKillNode, "kill_node"},
    {FaultKind::kCutLink, "cut_link"},
    {FaultKind::kFloodFrames, "flood_frames"},
    {FaultKind::kRotateKey, "rotate_key"},
    {FaultKind::kEstop, "estop"},
    {FaultKind::kRogueCommands, "rogue_commands"},
};

// Uniform in [lo, hi] from the generator's raw bits (the same sequence on every library).
int64_t uniform(std::mt19937_64& rng, int64_t lo, int64_t hi) {
  const uint64_t span = static_cast<uint64_t>(hi - lo) + 1;
  return lo + static_cast<int64_t>(rng() % span);
}

double unit(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * (1.0 / 9007199254740992.0);
}

int64_t duration_of(FaultKind kind, std::mt19937_64& rng) {
  constexpr int64_t kS = 1'000'000'000;
  switch (kind) {
    case FaultKind::kKillNode:
      return uniform(rng, kS / 2, 4 * kS);
    case FaultKind::kCutLink:
      return uniform(rng, 1 * kS, 6 * kS);
    case FaultKind::kFloodFrames:
      return uniform(rng, 2 * kS, 6 * kS);
    case FaultKind::kRotateKey:
      return 0;
    case FaultKind::kEstop:
      return uniform(rng, 2 * kS, 8 * kS);
    case FaultKind::kRogueCommands:
      return uniform(rng, 2 * kS, 5 * kS);
  }
  return 0;
}

}  // namespace

std::string_view to_string(FaultKind kind) {
  return util::name_of(kFaultNames, kind);
}

std::vector<Fault> plan_faults(const PlanParams& p, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<FaultKind> kinds = {FaultKind::kKillNode, FaultKind::kFloodFrames,
                                  FaultKind::kRotateKey, FaultKind::kEstop,
                                  FaultKind::kRogueCommands};
  if (p.link) kinds.push_back(FaultKind::kCutLink);
  // The first round has every kind once, in a seeded order.
  std::vector<FaultKind> round_order = kinds;
  for (size_t i = round_order.size(); i > 1; --i)
    std::swap(round_order[i - 1], round_order[static_cast<size_t>(rng() % i)]);
  std::vector<Fault> out;
  int64_t t = 0;
  for (size_t n = 0;; ++n) {
    const double gap = -std::log(1.0 - unit(rng)) * static_cast<double>(p.mean_gap_ns);
    t += std::max<int64_t>(p.min_gap_ns, static_cast<int64_t>(gap));
    if (t >= p.span_ns) break;
    Fault f;
    f.at_ns = t;
    f.kind = n < round_order.size() ? round_order[n] : kinds[rng() % kinds.size()];
    f.duration_ns = duration_of(f.kind, rng);
    f.node = static_cast<int>(rng() % static_cast<uint64_t>(std::max(1, p.nodes)));
    f.sigkill = (rng() & 1) != 0;
    out.push_back(f);
    t += f.duration_ns;
  }
  return out;
}

std::vector<Fault> first_round(const std::vector<Fault>& plan) {
  std::vector<Fault> out;
  for (const auto& f : plan) {
    const bool seen = std::any_of(out.begin(), out.end(),
                                  [&](const Fault& earlier) { return earlier.kind == f.kind; });
    if (seen) break;
    out.push_back(f);
  }
  return out;
}

}  // namespace stereoball::bench_chaos
