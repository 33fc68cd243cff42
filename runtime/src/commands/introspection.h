#pragma once
// Helpers shared by the commands that show types: load what is installed, describe a type.
#include <string>
#include <vector>

#include "plugin_manager.h"

namespace plugslam::runtime {

/// Loads every plugin on the search path; refusals are returned as one sentence each.
std::vector<std::string> loadAllPlugins(PluginManager& plugins);
/// Loads the plugin a type name ("laser2d.X") belongs to, if not loaded yet.
void loadPluginOf(PluginManager& plugins, const std::string& type);
/// What `describe` calls the top level of a config file (RunConfig, not a registered type).
inline constexpr const char* kTopLevelName = "run";
/// One line on the top level of a config file.
inline constexpr const char* kTopLevelDoc =
    "the keys of a config file's root map: the plugins, the source, the pipeline, the outputs "
    "and how the run goes";
/// The one top-level key that is no parameter of the run: read when the file is loaded.
inline constexpr const char* kBaseKeyDoc =
    "`base: FILE` starts from another config (a path relative to this file; a list of files: "
    "each written over the one before): this file's keys are written over FILE's, a map "
    "without `type:` changes FILE's key by key, anything else "
    "(a module with its `type:`, a list, a value) replaces it, and a key may be a --set path "
    "(`pipeline.tracker.splitter.distance`, `outputs[2]`; [n] with n = the list's length "
    "appends). `plugslam config --resolved FILE` prints the document a run uses";
/// Plain-text description of a type (or of kTopLevelName): parameters, nested modules, actions.
std::string describeType(const std::string& type);
/// Markdown reference of every registered type (docs/config-reference.md).
std::string configReferenceMarkdown(const std::vector<PluginInfo>& plugins);

}  // namespace plugslam::runtime
