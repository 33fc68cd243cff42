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
/// Plain-text description of a type: its parameters, nested modules and actions.
std::string describeType(const std::string& type);
/// Markdown reference of every registered type (docs/config-reference.md).
std::string configReferenceMarkdown(const std::vector<PluginInfo>& plugins);

}  // namespace plugslam::runtime
