#pragma once
// Finds, checks, loads and unloads plugins. A plugin is refused with one sentence (which plugin,
// built against what, the host has what) before any of its code beyond the descriptor runs.
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "plugslam/registry.h"

namespace plugslam::runtime {

/// A loaded plugin as the host sees it.
struct PluginInfo {
  std::string name;
  std::string version;
  std::string description;
  std::string sdk_version;
  std::string path;
  std::vector<std::string> types;
};

/// Loads plugins into a registry; objects created from a plugin keep its library mapped.
class PluginManager {
 public:
  explicit PluginManager(Registry& registry = Registry::instance());
  ~PluginManager();

  /// Adds a directory searched before the others (e.g. the config's folder).
  void addSearchDir(const std::string& dir);
  /// Where plugins are looked for, in order: added dirs, $PLUGSLAM_PLUGIN_PATH, the install dir,
  /// and the build tree's plugin folder when the host runs from the build tree.
  std::vector<std::string> searchPath() const;
  /// The file a plugin name resolves to, or "" when none is found.
  std::string resolve(const std::string& name_or_path) const;
  /// Every plugin file found on the search path (first one wins per name).
  std::vector<std::string> discover() const;

  /// Loads a plugin by name ("laser2d") or path ("./libfoo.so"); a no-op when already loaded
  /// from the same file. Throws PluginError with one sentence on any refusal.
  const PluginInfo& load(const std::string& name_or_path);
  /// True when a plugin of that name is loaded.
  bool isLoaded(const std::string& name) const;
  /// The loaded plugins, by name.
  std::vector<PluginInfo> loaded() const;
  /// Removes the plugin's types; its library is unmapped once no object made by it is alive.
  void unload(const std::string& name);
  /// True while objects created from the plugin are still alive.
  bool inUse(const std::string& name) const;

 private:
  struct Loaded;
  Registry& registry_;
  std::vector<std::string> extra_dirs_;
  std::map<std::string, std::unique_ptr<Loaded>> plugins_;
};

/// File name of a plugin on disk ("laser2d" -> "plugslam_laser2d.so").
std::string pluginFileName(const std::string& name);

}  // namespace plugslam::runtime
