#include "recorder/core/io_interfaces.hpp"

#include <algorithm>

namespace stereoball::recorder {

Status MemorySource::read(uint64_t offset, std::span<uint8_t> out) {
  if (offset > bytes_.size() || out.size() > bytes_.size() - offset) {
    return Error{"read of " + std::to_string(out.size()) + " bytes at offset " +
                 std::to_string(offset) + " is past the end (" + std::to_string(bytes_.size()) +
                 " bytes)"};
  }
  std::copy_n(bytes_.begin() + offset, out.size(), out.begin());
  return {};
}

Status MemorySpill::read(uint64_t offset, std::span<uint8_t> out) {
  return MemorySource(bytes_).read(offset, out);
}

}  // namespace stereoball::recorder
