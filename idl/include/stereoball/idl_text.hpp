#pragma once
#include <string_view>

namespace stereoball {
/// The complete text of idl/stereoball.idl (the MCAP schema of every channel).
std::string_view idl_text();
}  // namespace stereoball
