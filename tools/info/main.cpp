// stereoball-info FILE: duration, start/end, per topic type, count, rate and size, and whether
// the recording is complete (closed properly) or was cut off (read by linear scan).

#include <cstdio>
#include "common/util/cli11.hpp"

#include "recorder/core/file_info.hpp"
#include "recorder/io/file_io.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "stereoball info: summarize an MCAP recording (time span, topics with type, message "
      "count, rate and size) and say whether it is complete. Files cut off by a crash or a full "
      "disk are read by linear scan up to the last complete chunk."};
  std::string path;
  app.add_option("FILE", path, "MCAP file written by stereoball record")->required();
  CLI11_PARSE(app, argc, argv);

  auto source = stereoball::recorder::FileSource::open(path);
  if (!source) {
    std::fprintf(stderr, "stereoball info: %s\n", source.error().c_str());
    return 1;
  }
  auto info = stereoball::recorder::collect_file_info(**source);
  if (!info) {
    std::fprintf(stderr, "stereoball info: %s: %s\n", path.c_str(), info.error().c_str());
    return 1;
  }
  std::fputs(stereoball::recorder::format_file_info(*info, path).c_str(), stdout);
  if (info->nothing_readable()) {
    std::fprintf(stderr, "stereoball info: %s: no message could be read (see the notes above)\n",
                 path.c_str());
    return 1;
  }
  return 0;
}
