// Out-of-line destructors: they anchor each interface's vtable and type_info in the SDK, so
// dynamic_cast from plugin objects to SDK interfaces is resolved against one definition.
#include "plugslam/pipeline.h"
#include "plugslam/sink.h"
#include "plugslam/source.h"

namespace plugslam {
inline namespace abi_v1 {
Source::~Source() = default;

std::vector<ProvidedEntry> Source::provides() const {
  std::vector<ProvidedEntry> out;
  for (const EntryBase* e : entries())
    if (e->writes() && e->container() == Container::raw && !e->name().empty())
      out.push_back({e->name(), e->type()});
  return out;
}
PreProcessor::~PreProcessor() = default;
Sink::~Sink() = default;
}  // namespace abi_v1
}  // namespace plugslam
