#pragma once
// A whole run through the host's own path (load, `--set`, build, run), as `plugslam run` does it,
// for the tests that link plugslam_runtime.
#include <string>
#include <vector>

#include "config_builder.h"
#include "plugin_manager.h"
#include "run_config.h"
#include "runner.h"
#include "test_paths.h"

namespace plugslam::testing {

/// configs/<file> of this checkout with the `--set` assignments `sets` applied.
inline runtime::ConfigDocument shippedConfig(const std::string& file,
                                             const std::vector<std::string>& sets = {}) {
  runtime::ConfigDocument doc = runtime::loadConfigFile(sourceDir() + "/configs/" + file);
  for (const auto& s : sets) runtime::applyOverride(doc, s);
  return doc;
}

/// Builds `doc`, loading the plugins it names, and runs it with its outputs in `out_dir`. The
/// plugins stay loaded in `plugins` when it is given: a test that creates their types afterwards
/// needs them (unloading a plugin removes its types).
inline runtime::RunReport runDocument(const runtime::ConfigDocument& doc,
                                      const std::string& out_dir,
                                      runtime::PluginManager* plugins = nullptr) {
  runtime::PluginManager own;
  auto run = runtime::buildRun(doc, plugins ? *plugins : own);
  runtime::RunOptions options;
  options.out_dir = out_dir;
  return runtime::runPipeline(*run, options);
}

}  // namespace plugslam::testing
