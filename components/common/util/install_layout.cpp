#include "common/util/install_layout.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>

namespace stereoball::paths {
namespace fs = std::filesystem;

namespace {

// Set by CMake for the copy of a program that runs from its build tree; an installed copy
// has the same strings compiled in but is never found inside these folders.
#ifndef SB_BUILD_BIN_DIRS
#define SB_BUILD_BIN_DIRS ""
#endif
#ifndef SB_BUILD_SOURCE_DIR
#define SB_BUILD_SOURCE_DIR ""
#endif

constexpr const char* kEtcDir = "/etc/stereoball";

std::vector<fs::path> split_dirs(std::string_view list) {
  std::vector<fs::path> dirs;
  size_t start = 0;
  while (start <= list.size()) {
    const size_t end = std::min(list.find(':', start), list.size());
    if (end > start) dirs.emplace_back(std::string(list.substr(start, end - start)));
    start = end + 1;
  }
  return dirs;
}

bool same_dir(const fs::path& a, const fs::path& b) {
  std::error_code ec;
  return fs::equivalent(a, b, ec);
}

// Why a candidate cannot be used, or "" when it can. A name with an extension ("tracker.yaml")
// must be a file, one without ("scenarios") a folder.
std::string unreadable_reason(const fs::path& path) {
  std::error_code ec;
  const bool want_folder = !path.has_extension();
  if (fs::is_directory(path, ec)) {
    if (!want_folder) return "a folder, not a file";
    return access(path.c_str(), R_OK | X_OK) == 0 ? "" : std::strerror(errno);
  }
  if (want_folder) return "not a folder";
  if (!fs::is_regular_file(path, ec)) return "not a regular file";
  std::ifstream in(path);
  return in ? "" : std::strerror(errno);
}

struct Candidate {
  fs::path path;
  std::string origin;
};

std::vector<Candidate> candidates(std::string_view name, const SearchRoots& roots) {
  std::vector<Candidate> out;
  if (roots.env_config_dir) out.push_back({*roots.env_config_dir / name, "$STEREOBALL_CONFIG_DIR"});
  if (roots.etc_dir) out.push_back({*roots.etc_dir / name, roots.etc_dir->string()});
  if (roots.share_dir) out.push_back({*roots.share_dir / "config" / name, "installed files"});
  if (roots.source_dir) out.push_back({*roots.source_dir / "config" / name, "source tree"});
  return out;
}

}  // namespace

SearchRoots roots_for_executable(const fs::path& exe_path,
                                 const std::vector<fs::path>& build_bin_dirs,
                                 const std::optional<fs::path>& source_dir) {
  SearchRoots roots;
  roots.etc_dir = fs::path(kEtcDir);
  const fs::path exe_dir = exe_path.parent_path();
  std::error_code ec;
  for (const fs::path& up :
       {exe_dir / ".." / "share" / "stereoball", exe_dir / ".." / ".." / "share" / "stereoball"}) {
    if (fs::is_directory(up / "config", ec)) {
      roots.share_dir = fs::weakly_canonical(up, ec);
      break;
    }
  }
  if (source_dir) {
    for (const auto& bin : build_bin_dirs) {
      if (same_dir(exe_dir, bin)) roots.source_dir = *source_dir;
    }
  }
  return roots;
}

fs::path executable_dir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path(".") : exe.parent_path();
}

SearchRoots default_roots() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  const std::string source = SB_BUILD_SOURCE_DIR;
  SearchRoots roots =
      roots_for_executable(ec ? fs::path("./unknown") : exe, split_dirs(SB_BUILD_BIN_DIRS),
                           source.empty() ? std::nullopt : std::optional<fs::path>(source));
  if (const char* dir = std::getenv("STEREOBALL_CONFIG_DIR"); dir && *dir) {
    roots.env_config_dir = fs::path(dir);
  }
  return roots;
}

Result<Found> find_config(std::string_view name, const SearchRoots& roots) {
  std::string tried;
  for (const auto& candidate : candidates(name, roots)) {
    std::error_code ec;
    if (!fs::exists(candidate.path, ec)) {
      tried += "\n  " + candidate.path.string() + " (" + candidate.origin + "): not there";
      continue;
    }
    if (auto reason = unreadable_reason(candidate.path); !reason.empty()) {
      return Error{candidate.path.string() + " (" + candidate.origin +
                   ") exists but cannot be read: " + reason};
    }
    return Found{candidate.path, candidate.origin};
  }
  if (tried.empty()) tried = "\n  (no folder to search: installed files and source tree unknown)";
  return Error{"no " + std::string(name) + " found; tried, in order:" + tried +
               "\n  (give one with --config FILE or set STEREOBALL_CONFIG_DIR)"};
}

std::string shipped_config_path(std::string_view name) {
  if (auto found = find_config(name, default_roots())) return found->path.string();
  return (fs::path("config") / name).string();
}

std::string shipped_config_dir() {
  if (auto root = data_root(default_roots())) return (*root / "config").string();
  return "config";
}

Result<Found> check_explicit(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) return Error{path.string() + ": no such file"};
  if (auto reason = unreadable_reason(path); !reason.empty()) {
    return Error{path.string() + ": cannot be read: " + reason};
  }
  return Found{path, "--config"};
}

Result<fs::path> data_root(const SearchRoots& roots) {
  if (roots.share_dir) return *roots.share_dir;
  if (roots.source_dir) return *roots.source_dir;
  return Error{
      "cannot find StereoBall's data folder: neither <prefix>/share/stereoball beside this "
      "program nor the source tree of a build-tree program"};
}

}  // namespace stereoball::paths
