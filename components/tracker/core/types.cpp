#include "tracker/core/types.hpp"

#include "common/util/enum_names.hpp"

namespace stereoball::tracker {

bool is_accepted(Verdict v) {
  return v == Verdict::kStartupAccepted || v == Verdict::kBlockMatchAccepted ||
         v == Verdict::kStatisticsAccepted;
}

namespace {

constexpr util::EnumName<TrackState> kTrackStateNames[] = {
    {TrackState::kIdle, "idle"},
    {TrackState::kFollowing, "following"},
    {TrackState::kSearching, "searching"},
};

constexpr util::EnumName<Side> kSideNames[] = {
    {Side::kLeft, "left"},
    {Side::kRight, "right"},
    {Side::kUnknown, "unknown"},
};

constexpr util::EnumName<Verdict> kVerdictNames[] = {
    {Verdict::kNoDetection, "no_detection"},
    {Verdict::kStartupCollecting, "startup_collecting"},
    {Verdict::kStartupInconsistent, "startup_inconsistent"},
    {Verdict::kStartupAccepted, "startup_accepted"},
    {Verdict::kBlockMatchAccepted, "block_match_accepted"},
    {Verdict::kStatisticsAccepted, "statistics_accepted"},
    {Verdict::kRejected, "rejected"},
};

}  // namespace

std::string_view to_string(TrackState s) {
  return util::name_of(kTrackStateNames, s);
}

std::string_view to_string(Side s) {
  return util::name_of(kSideNames, s);
}

std::string_view to_string(Verdict v) {
  return util::name_of(kVerdictNames, v);
}

}  // namespace stereoball::tracker
