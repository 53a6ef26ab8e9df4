// libFuzzer target: the MCAP reader (stereoball info/play) on arbitrary file bytes.

#include <cstddef>
#include <cstdint>
#include <span>

#include "recorder/core/file_info.hpp"
#include "recorder/core/reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace stereoball::recorder;
  const std::span<const uint8_t> bytes(data, size);
  MemorySource source(bytes);
  McapReader reader(source);
  if (reader.open().ok()) {
    reader.for_each_message([](const MessageView& m) { return m.data.size() < (1u << 30); });
    reader.check_message_indexes();
  }
  MemorySource again(bytes);
  if (auto info = collect_file_info(again)) format_file_info(*info, "fuzz.mcap");
  return 0;
}
