#pragma once
// Loads a deploy profile the way an installed or build-tree program finds its data
// (common/util/install_layout.hpp): profiles from the data root's deploy/, every
// "{config}/NAME" through the configuration search order.

#include <filesystem>
#include <string>

#include "common/util/result.hpp"
#include "profile.hpp"

namespace stereoball::launch {

/// A profile by name or path, with its files resolved for this process; the data root used
/// is stored in root_dir (for messages).
Result<Profile> load_profile_for_this_program(const std::string& name_or_path,
                                              std::filesystem::path* root_dir = nullptr);

}  // namespace stereoball::launch
