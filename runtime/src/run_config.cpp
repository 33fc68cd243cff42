#include "run_config.h"

#include "entry_check.h"
#include "plugslam/errors.h"

namespace plugslam::runtime {

std::shared_ptr<RunConfig> buildRun(const ConfigDocument& doc, PluginManager& plugins) {
  ConfigBuilder builder(doc, plugins);
  builder.loadPlugins("plugins");
  auto run = std::make_shared<RunConfig>();
  run->setTypeName("run");
  run->setName("run");
  if (!doc.root["source"] || doc.root["source"].IsNull())
    builder.report(doc.root["source"] ? doc.root["source"] : doc.root, "source",
                   "missing 'source:' (where frames come from)");
  builder.configureRoot(*run);  // throws every error found, this one included
  if (!run->source)
    builder.fail(doc.root, "source", "missing 'source:' (where frames come from)");
  checkEntries(*run, doc, builder);
  builder.check();
  return run;
}

size_t countModules(const Configurable& root) {
  size_t n = 1;
  for (auto* s : root.slots())
    for (auto& item : s->items()) n += countModules(*item);
  return n;
}

}  // namespace plugslam::runtime
