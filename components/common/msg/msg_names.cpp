#include "common/msg/msg_names.hpp"

#include "common/util/enum_names.hpp"
#include "stereoball.h"

#include <algorithm>
#include <cctype>

namespace stereoball::msg {
namespace {

constexpr util::EnumName<std::int32_t> kStatusNames[] = {
    {stereoball_msg_DETECTION_FOUND, "FOUND"},
    {stereoball_msg_DETECTION_NO_CANDIDATE, "NO_CANDIDATE"},
    {stereoball_msg_DETECTION_EPIPOLAR_MISMATCH, "EPIPOLAR_MISMATCH"},
    {stereoball_msg_DETECTION_SIZE_INCONSISTENT, "SIZE_INCONSISTENT"},
    {stereoball_msg_DETECTION_NO_CALIBRATION, "NO_CALIBRATION"},
    {stereoball_msg_DETECTION_BAD_FRAME, "BAD_FRAME"},
    {stereoball_msg_DETECTION_OFF_FLOOR, "OFF_FLOOR"},
    {stereoball_msg_DETECTION_INTERIOR_MISMATCH, "INTERIOR_MISMATCH"},
};

constexpr util::EnumName<std::int32_t> kStateNames[] = {
    {stereoball_msg_TRACK_IDLE, "IDLE"},
    {stereoball_msg_TRACK_FOLLOWING, "FOLLOWING"},
    {stereoball_msg_TRACK_SEARCHING, "SEARCHING"},
};

constexpr util::EnumName<std::int32_t> kSideNames[] = {
    {stereoball_msg_SIDE_UNKNOWN, "UNKNOWN"},
    {stereoball_msg_SIDE_LEFT, "LEFT"},
    {stereoball_msg_SIDE_RIGHT, "RIGHT"},
};

constexpr util::EnumName<std::int32_t> kVerdictNames[] = {
    {stereoball_msg_VERDICT_NO_DETECTION, "NO_DETECTION"},
    {stereoball_msg_VERDICT_STARTUP_COLLECTING, "STARTUP_COLLECTING"},
    {stereoball_msg_VERDICT_STARTUP_INCONSISTENT, "STARTUP_INCONSISTENT"},
    {stereoball_msg_VERDICT_STARTUP_ACCEPTED, "STARTUP_ACCEPTED"},
    {stereoball_msg_VERDICT_BLOCK_MATCH_ACCEPTED, "BLOCK_MATCH_ACCEPTED"},
    {stereoball_msg_VERDICT_STATISTICS_ACCEPTED, "STATISTICS_ACCEPTED"},
    {stereoball_msg_VERDICT_REJECTED, "REJECTED"},
};

}  // namespace

std::optional<std::string_view> detection_status_name(std::int32_t value) {
  return util::find_name(kStatusNames, value);
}

std::optional<std::string_view> track_state_name(std::int32_t value) {
  return util::find_name(kStateNames, value);
}

std::optional<std::string_view> side_name(std::int32_t value) {
  return util::find_name(kSideNames, value);
}

std::optional<std::string_view> track_verdict_name(std::int32_t value) {
  return util::find_name(kVerdictNames, value);
}

std::string lower_or_number(std::optional<std::string_view> name, std::int32_t value) {
  if (!name) return "unknown(" + std::to_string(value) + ")";
  std::string lower(*name);
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return lower;
}

}  // namespace stereoball::msg
