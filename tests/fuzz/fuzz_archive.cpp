// Session / container loader: makeInArchive (binary or text back-end, chosen like
// loadArchiveFile does, by the magic) and load(PropertyContainer).
#include <sstream>

#include "fuzz_common.h"
#include "plugslam/archive.h"
#include "plugslam/errors.h"
#include "plugslam/property_container.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes = plugslam::fuzz::text(data, size);
  const auto format = bytes.rfind("PLSB", 0) == 0 ? plugslam::ArchiveFormat::kBinary
                                                  : plugslam::ArchiveFormat::kText;
  try {
    std::istringstream in(bytes);
    auto archive = plugslam::makeInArchive(in, format, "fuzz");
    plugslam::PropertyContainer container;
    load(*archive, container);
  } catch (const plugslam::Error&) {
  }
  return 0;
}
