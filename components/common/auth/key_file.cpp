#include "common/auth/key_file.hpp"

#include <fcntl.h>
#include <sodium.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace stereoball::auth {
namespace {

constexpr const char* kHeader = "stereoball-keys 1";

std::string to_hex(const Key& key) {
  char hex[kKeyBytes * 2 + 1];
  sodium_bin2hex(hex, sizeof hex, key.data(), key.size());
  return hex;
}

std::optional<Key> from_hex(const std::string& hex) {
  Key key;
  size_t length = 0;
  if (hex.size() != kKeyBytes * 2) return std::nullopt;
  if (sodium_hex2bin(key.data(), key.size(), hex.data(), hex.size(), nullptr, &length, nullptr) !=
          0 ||
      length != kKeyBytes) {
    return std::nullopt;
  }
  return key;
}

// One "key ..." line, or the reason it is malformed.
Result<KeyEntry> parse_key_line(std::istringstream& in) {
  KeyEntry entry;
  std::string role, hex;
  if (!(in >> entry.id >> role)) return Error{"expected 'key <id> <role> ...'"};
  if (role == "sign") {
    entry.signs = true;
  } else if (role == "accept-until") {
    if (!(in >> entry.accept_until_ns)) return Error{"accept-until needs a time in ns"};
  } else if (role != "staged") {
    return Error{"unknown role '" + role + "' (sign, accept-until, staged)"};
  }
  if (!(in >> hex)) return Error{"missing key"};
  const auto key = from_hex(hex);
  if (!key) return Error{"key must be 64 hex digits"};
  entry.key = *key;
  std::string extra;
  if (in >> extra) return Error{"unexpected '" + extra + "'"};
  return entry;
}

uint32_t next_id(const Keyring& ring) {
  uint32_t id = 0;
  for (const auto& k : ring.keys) id = std::max(id, k.id);
  return id + 1;
}

}  // namespace

Status check_key_file_mode(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return Error{"key file " + path + " not found"};
  if (!S_ISREG(st.st_mode)) return Error{"key file " + path + " is not a regular file"};
  if ((st.st_mode & 077) != 0) {
    char mode[8];
    std::snprintf(mode, sizeof mode, "%04o", static_cast<unsigned>(st.st_mode & 07777));
    return Error{"key file " + path + " is accessible by others (mode " + mode +
                 "): anyone who can read it can move the robot; run 'chmod 600 " + path + "'"};
  }
  return {};
}

Result<Keyring> load_key_file(const std::string& path) {
  if (auto e = check_key_file_mode(path); !e) return Error{e.error()};
  std::ifstream file(path);
  if (!file) return Error{"key file " + path + " cannot be read"};
  Keyring ring;
  std::string line;
  int number = 0;
  bool header = false;
  while (std::getline(file, line)) {
    ++number;
    const std::string where = "key file " + path + " line " + std::to_string(number) + ": ";
    if (line.empty() || line[0] == '#') continue;
    if (!header) {
      if (line != kHeader) return Error{where + "expected '" + kHeader + "'"};
      header = true;
      continue;
    }
    std::istringstream in(line);
    std::string word;
    in >> word;
    if (word != "key") return Error{where + "expected 'key ...'"};
    auto entry = parse_key_line(in);
    if (!entry) return Error{where + entry.error()};
    ring.keys.push_back(*entry);
  }
  if (!header) return Error{"key file " + path + " is empty"};
  if (auto e = ring.validate(); !e) return Error{"key file " + path + ": " + e.error()};
  return ring;
}

Status save_key_file(const std::string& path, const Keyring& ring) {
  if (auto e = ring.validate(); !e) return Error{"refusing to write " + path + ": " + e.error()};
  std::ostringstream text;
  text << "# StereoBall deployment keys: secret, mode 0600 (stereoball keys init|show|rotate)\n"
       << kHeader << "\n";
  for (const auto& k : ring.keys) {
    text << "key " << k.id << " ";
    if (k.signs) {
      text << "sign ";
    } else if (k.accept_until_ns != INT64_MAX) {
      text << "accept-until " << k.accept_until_ns << " ";
    } else {
      text << "staged ";
    }
    text << to_hex(k.key) << "\n";
  }
  const std::string tmp = path + ".tmp" + std::to_string(::getpid());
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd < 0) return Error{"cannot create " + tmp};
  // A rotation run as root keeps the file the service user's (it must stay readable to the
  // nodes, which run as that user); a failure here only means we are not root.
  struct stat old_file {};
  if (::stat(path.c_str(), &old_file) == 0) {
    [[maybe_unused]] const int kept = ::fchown(fd, old_file.st_uid, old_file.st_gid);
  }
  const std::string bytes = text.str();
  const bool written =
      ::write(fd, bytes.data(), bytes.size()) == static_cast<ssize_t>(bytes.size());
  const bool synced = ::fsync(fd) == 0;
  ::close(fd);
  if (!written || !synced || ::rename(tmp.c_str(), path.c_str()) != 0) {
    ::unlink(tmp.c_str());
    return Error{"cannot write key file " + path};
  }
  return {};
}

Keyring new_keyring() {
  Keyring ring;
  ring.keys.push_back(KeyEntry{1, random_key(), true, INT64_MAX});
  return ring;
}

Keyring rotate(const Keyring& ring, int64_t now_ns, int64_t grace_ns) {
  Keyring out;
  bool promoted = false;
  for (const auto& k : ring.keys) {
    if (k.accept_until_ns <= now_ns) continue;  // grace over
    KeyEntry entry = k;
    if (k.signs) {
      entry.signs = false;
      entry.accept_until_ns = now_ns + grace_ns;
    } else if (k.accept_until_ns == INT64_MAX && !promoted) {
      entry.signs = true;  // the staged key
      promoted = true;
    }
    out.keys.push_back(entry);
  }
  if (!promoted) out.keys.push_back(KeyEntry{next_id(ring), random_key(), true, INT64_MAX});
  return out;
}

Keyring stage(const Keyring& ring) {
  Keyring out = ring;
  out.keys.push_back(KeyEntry{next_id(ring), random_key(), false, INT64_MAX});
  return out;
}

std::string describe(const Keyring& ring, int64_t now_ns) {
  std::ostringstream out;
  for (const auto& k : ring.keys) {
    // Fingerprint: first 8 bytes of a hash of the key, enough to compare hosts' files.
    unsigned char hash[crypto_generichash_BYTES];
    crypto_generichash(hash, sizeof hash, k.key.data(), k.key.size(), nullptr, 0);
    char fingerprint[17];
    sodium_bin2hex(fingerprint, sizeof fingerprint, hash, 8);
    out << "key " << k.id << "  fingerprint " << fingerprint << "  ";
    if (k.signs) {
      out << "signs";
    } else if (k.accept_until_ns == INT64_MAX) {
      out << "staged (accepted, signs after 'keys rotate')";
    } else if (k.accept_until_ns <= now_ns) {
      out << "expired";
    } else {
      out << "accepted for " << (k.accept_until_ns - now_ns) / 1'000'000'000 << " s more";
    }
    out << "\n";
  }
  return out.str();
}

}  // namespace stereoball::auth
