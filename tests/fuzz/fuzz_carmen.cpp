// CARMEN log parser (CarmenReader::fromText), strict and skip policies.
#include "fuzz_common.h"
#include "plugslam/errors.h"
#include "readers/carmen_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  for (auto policy : {plugslam::io::ErrorPolicy::kStrict, plugslam::io::ErrorPolicy::kSkip}) {
    plugslam::io::CarmenReaderOptions options;
    options.policy = policy;
    options.emit_params = true;
    options.max_line_bytes = 1 << 16;
    std::size_t warnings = 0;
    options.on_warning = [&](const plugslam::io::ReaderWarning&) { ++warnings; };
    try {
      auto reader = plugslam::io::CarmenReader::fromText("fuzz.log",
                                                         plugslam::fuzz::text(data, size), options);
      plugslam::io::CarmenRecord record;
      while (reader->next(record)) {
      }
    } catch (const plugslam::Error&) {
    }
  }
  return 0;
}
