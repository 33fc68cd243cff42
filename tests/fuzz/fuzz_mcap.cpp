// MCAP reader (mcap::Reader::fromBytes, indexed and scanned) and the CDR decoders on its messages.
#include "fuzz_common.h"
#include "plugslam/errors.h"
#include "plugslam/mcap/reader.h"
#include "readers/cdr_messages.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  for (const bool summary : {true, false}) {
    plugslam::mcap::ReaderOptions options;
    options.use_summary = summary;
    options.max_record_bytes = 1 << 24;
    try {
      auto reader = plugslam::mcap::Reader::fromBytes("fuzz.mcap",
                                                      plugslam::fuzz::text(data, size), options);
      plugslam::mcap::ReadMessage m;
      while (reader->next(m)) {
        const auto* p = reinterpret_cast<const std::uint8_t*>(m.data.data());
        try {
          plugslam::io::LaserScanMsg scan;
          plugslam::io::decodeCdr(p, m.data.size(), scan);
        } catch (const plugslam::Error&) {
        }
        try {
          plugslam::io::TfMsg tf;
          plugslam::io::decodeCdr(p, m.data.size(), tf);
        } catch (const plugslam::Error&) {
        }
      }
    } catch (const plugslam::Error&) {
    }
  }
  return 0;
}
