#pragma once
// The deployment key file: read (refused when others can read it), written atomically with
// mode 0600, created and rotated. Text format, one key a line:
//   stereoball-keys 1
//   key <id> sign <64 hex>                      the key that signs (exactly one)
//   key <id> accept-until <ns> <64 hex>         rotated out: still accepted until <ns>
//   key <id> staged <64 hex>                    next key: accepted, signs after `rotate`

#include <cstdint>
#include <string>

#include "common/auth/auth.hpp"
#include "common/util/result.hpp"

namespace stereoball::auth {

/// Reads path; an error names the file and the problem (missing, mode, syntax, ring).
Result<Keyring> load_key_file(const std::string& path);
/// Writes ring to path with mode 0600 (temporary file + rename: readers never see half).
Status save_key_file(const std::string& path, const Keyring& ring);
/// Error text if path is readable or writable by group or others, or not a regular file.
Status check_key_file_mode(const std::string& path);

/// A new ring with one random signing key (id 1).
Keyring new_keyring();
/// Rotation at now_ns: the staged key (or a new one) signs; the old signing key is accepted
/// for grace_ns more; keys whose grace has ended are dropped.
Keyring rotate(const Keyring& ring, int64_t now_ns, int64_t grace_ns);
/// Adds a staged key (accepted everywhere the file is copied, signing after rotate()).
Keyring stage(const Keyring& ring);

/// Lines for `stereoball keys show`: id, role, expiry and a fingerprint, never the key.
std::string describe(const Keyring& ring, int64_t now_ns);

}  // namespace stereoball::auth
