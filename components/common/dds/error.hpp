#pragma once
// Errors of the DDS layer carry Cyclone's own text (dds_strretcode).

#include <stdexcept>
#include <string>

namespace stereoball::dds {

/// A DDS call failed; what() names the operation and Cyclone's reason.
class Error : public std::runtime_error {
 public:
  Error(const std::string& operation, int return_code);
  int code() const { return code_; }

 private:
  int code_;
};

/// Throws Error if rc is negative; returns rc otherwise.
int check(int rc, const char* operation);

}  // namespace stereoball::dds
