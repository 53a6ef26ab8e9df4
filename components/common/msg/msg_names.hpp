#pragma once
// Names of the IDL enums (idl/stereoball.idl), one table each, for every tool that prints or
// writes a message: `stereoball topic` prints the IDL spelling ("NO_CANDIDATE"), JSON and
// reports the lower-case one ("no_candidate").

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace stereoball::msg {

/// DetectionStatus in IDL spelling without the prefix ("FOUND"); nullopt outside the enum.
std::optional<std::string_view> detection_status_name(std::int32_t value);
/// TrackState in IDL spelling ("FOLLOWING"); nullopt outside the enum.
std::optional<std::string_view> track_state_name(std::int32_t value);
/// Side in IDL spelling ("LEFT"); nullopt outside the enum.
std::optional<std::string_view> side_name(std::int32_t value);
/// TrackVerdict in IDL spelling ("BLOCK_MATCH_ACCEPTED"); nullopt outside the enum.
std::optional<std::string_view> track_verdict_name(std::int32_t value);

/// The lower-case spelling of a name ("no_candidate"), or "unknown(N)" for a value outside
/// the enum (N the raw value), as JSON, the viewer and reports write it.
std::string lower_or_number(std::optional<std::string_view> name, std::int32_t value);

}  // namespace stereoball::msg
