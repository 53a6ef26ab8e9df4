#include "simulator/core/render_lead.hpp"

#include <algorithm>

namespace stereoball::simulator {

RenderLead::RenderLead(int64_t initial_ns, int64_t period_ns, int window_frames)
    : period_ns_(period_ns),
      window_frames_(static_cast<std::size_t>(std::max(1, window_frames))),
      lead_ns_(std::clamp<int64_t>(initial_ns, kMarginNs,
                                   std::max(kMarginNs, period_ns - kMarginNs / 2))),
      min_lead_ns_(lead_ns_),
      max_lead_ns_(lead_ns_) {}

int64_t RenderLead::lead_for(int64_t slowest_ns, int64_t period_ns) {
  // 5/4: a frame a quarter slower than the slowest recent one is still on time.
  const int64_t upper = std::max(kMarginNs, period_ns - kMarginNs / 2);
  return std::clamp<int64_t>(slowest_ns * 5 / 4 + kMarginNs, kMarginNs, upper);
}

void RenderLead::add_work(int64_t work_ns) {
  if (work_ns < 0) return;
  work_ns_.push_back(work_ns);
  if (work_ns_.size() > window_frames_) work_ns_.pop_front();
  lead_ns_ = lead_for(*std::max_element(work_ns_.begin(), work_ns_.end()), period_ns_);
  min_lead_ns_ = std::min(min_lead_ns_, lead_ns_);
  max_lead_ns_ = std::max(max_lead_ns_, lead_ns_);
}

}  // namespace stereoball::simulator
