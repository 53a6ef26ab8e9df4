#include "installed_profile.hpp"

#include "common/util/install_layout.hpp"

namespace stereoball::launch {

Result<Profile> load_profile_for_this_program(const std::string& name_or_path,
                                              std::filesystem::path* root_dir) {
  const paths::SearchRoots roots = paths::default_roots();
  auto root = paths::data_root(roots);
  if (!root) return Error{root.error()};
  if (root_dir) *root_dir = *root;
  const ConfigLookup lookup = [&roots](std::string_view name) -> Result<std::string> {
    auto found = paths::find_config(name, roots);
    if (!found) return Error{found.error()};
    return found->path.string();
  };
  return load_profile(name_or_path, root->string(), lookup);
}

}  // namespace stereoball::launch
