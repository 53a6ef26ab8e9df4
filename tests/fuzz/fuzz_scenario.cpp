// libFuzzer target: simulator scenario files (config/scenarios/*.yaml) on arbitrary text.

#include <cstddef>
#include <cstdint>
#include <string>

#include "simulator/io/scenario_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  (void)stereoball::simulator::parse_scenario(text, "fuzz.yaml");
  return 0;
}
