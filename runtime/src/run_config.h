#pragma once
// The root of a config file: which plugins, the source, the pipeline and the outputs.
#include <memory>
#include <string>
#include <vector>

#include "config_builder.h"
#include "plugin_manager.h"
#include "plugslam/pipeline.h"
#include "plugslam/sink.h"
#include "plugslam/source.h"

namespace plugslam::runtime {

/// The document root of a run config.
class RunConfig : public Configurable {
 public:
  static constexpr const char* kKind = "Run";
  Param<std::vector<std::string>> plugins{this, "plugins", {}, "",
                                          "plugins to load, by name or path"};
  Slot<Source> source{this, "source", "", "where frames come from"};
  Slot<Pipeline> pipeline{this, "pipeline", "sdk.Pipeline", "the processing chain"};
  SlotList<Sink> outputs{this, "outputs", "writers and streams fed each frame and at the end"};
  Param<int64_t> max_frames{this, "max_frames", 0, "", "stop after this many frames (0: all)",
                            Range{0, 1e15}};
  // Decoding images (PNG, JPEG, bag messages) costs as much as tracking them: done on a thread
  // of its own, the two overlap. A few frames absorb the jitter of either side.
  Param<int64_t> read_ahead{this, "read_ahead", 4, "frames",
                            "frames the source reads and decodes ahead of the pipeline, on a "
                            "thread of its own (0: read on the pipeline's thread)",
                            Range{0, 1000}};
  Param<std::string> on_module_error{
      this, "on_module_error", "stop", "",
      "a module that throws during a run: stop (outputs written, session saved in "
      "OUTDIR/session, exit 1) or skip the frame (warned, counted in run.json)",
      Choices{{"stop", "skip"}}};
};

/// Loads the config's plugins and builds the whole module tree; throws ConfigError/PluginError.
std::shared_ptr<RunConfig> buildRun(const ConfigDocument& doc, PluginManager& plugins);

/// Counts the modules of a tree (the root included).
size_t countModules(const Configurable& root);

}  // namespace plugslam::runtime
