// YAML pipeline builder: loadConfigText + buildRun with the SDK's types (the config's plugin
// list is dropped so the fuzzer never dlopens a path it made up), then --set path splitting of
// the first line.
#include <yaml-cpp/yaml.h>

#include "config_builder.h"
#include "fuzz_common.h"
#include "plugin_manager.h"
#include "plugslam/errors.h"
#include "run_config.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text = plugslam::fuzz::text(data, size);
  try {
    plugslam::runtime::splitPath(text.substr(0, text.find('\n')));
  } catch (const plugslam::Error&) {
  }
  try {
    auto doc = plugslam::runtime::loadConfigText(text, "fuzz.yaml");
    if (doc.root.IsMap()) doc.root.remove("plugins");
    plugslam::runtime::PluginManager plugins;
    plugslam::runtime::buildRun(doc, plugins);
  } catch (const plugslam::Error&) {
  }
  return 0;
}
