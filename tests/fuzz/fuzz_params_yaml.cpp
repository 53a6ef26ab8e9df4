// libFuzzer target: component parameter files (common/params + the tracker's and
// ball_detector's readers) and launch profiles' strict YAML loading, on arbitrary text.

#include <cstddef>
#include <cstdint>
#include <string>

#include "ball_detector/pipeline/detector_params_file.hpp"
#include "common/params/params_file.hpp"
#include "common/params/yaml_load.hpp"
#include "tracker/node/tracker_params_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  namespace sb = stereoball;
  const std::string text(reinterpret_cast<const char*>(data), size);
  if (auto tracker = sb::params::ParamsFile::parse(text, "fuzz.yaml")) {
    (void)sb::tracker::read_tracker_params(*tracker);
  }
  if (auto detector = sb::params::ParamsFile::parse(text, "fuzz.yaml")) {
    (void)sb::ball_detector::read_detector_params(*detector);
  }
  if (auto file = sb::params::ParamsFile::parse(text, "fuzz.yaml")) {
    double d = 0;
    int i = 0;
    bool b = false;
    std::string s;
    std::vector<double> v;
    file->read("a.b", d, -1.0, 1.0);
    file->read("n", i, 0, 10);
    file->read("flag", b);
    file->read_choice("mode", s, {"x", "y"});
    file->read("list", v, 3);
    (void)file->finish();
  }
  return 0;
}
