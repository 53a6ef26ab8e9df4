#include "simulator/core/render_lead.hpp"

#include <algorithm>
#include <vector>

namespace stereoball::simulator {

RenderLead::RenderLead(int64_t initial_ns, int64_t period_ns, int window_frames)
    : period_ns_(period_ns),
      window_frames_(static_cast<std::size_t>(std::max(1, window_frames))),
      lead_ns_(std::clamp<int64_t>(initial_ns, kMarginNs,
                                   std::max(kMarginNs, period_ns - kMarginNs / 2))),
      min_lead_ns_(lead_ns_),
      max_lead_ns_(lead_ns_) {}

int64_t RenderLead::lead_for(int64_t work_ns, int64_t period_ns) {
  // 5/4: a frame a quarter slower than most recent ones is still on time.
  const int64_t upper = std::max(kMarginNs, period_ns - kMarginNs / 2);
  return std::clamp<int64_t>(work_ns * 5 / 4 + kMarginNs, kMarginNs, upper);
}

void RenderLead::add_work(int64_t work_ns) {
  if (work_ns < 0) return;
  work_ns_.push_back(work_ns);
  if (work_ns_.size() > window_frames_) work_ns_.pop_front();
  // The 90th percentile, not the slowest: a render slowed once by other work on the cores
  // would otherwise hold the lead up for a whole window, starting the next renders beside
  // the processing of the frames before them, which slows those renders in turn.
  std::vector<int64_t> sorted(work_ns_.begin(), work_ns_.end());
  const auto at = sorted.begin() + static_cast<std::ptrdiff_t>((sorted.size() - 1) * 9 / 10);
  std::nth_element(sorted.begin(), at, sorted.end());
  lead_ns_ = lead_for(*at, period_ns_);
  min_lead_ns_ = std::min(min_lead_ns_, lead_ns_);
  max_lead_ns_ = std::max(max_lead_ns_, lead_ns_);
}

}  // namespace stereoball::simulator
