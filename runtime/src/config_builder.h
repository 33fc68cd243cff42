#pragma once
// Builds module trees from YAML through the registry. Every error names the file, line and
// column, the path in the pipeline ("pipeline.tracker.aligner.slices[1].max_distance") and what
// was expected; unknown keys are errors, near misses get a "did you mean". A build goes on past
// an error to the next key or list item, so one pass reports every error in the file.
#include <yaml-cpp/yaml.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "plugin_manager.h"
#include "plugslam/configurable.h"
#include "plugslam/registry.h"

namespace plugslam::runtime {

/// A YAML document, its bases resolved, with the command line's --set overrides applied.
struct ConfigDocument {
  std::string file;  ///< the file given, shown in error messages on what it wrote
  YAML::Node root;
  std::map<std::string, std::string> overrides;  ///< pipeline path -> "--set path=value"
  /// Which file wrote what, when the config starts from a base: pipeline path -> file. A value
  /// was written by the file of the longest path listed that is its path or holds it, else by
  /// `file` (sourceOf). Nodes keep the line and column where that file wrote them.
  std::map<std::string, std::string> sources;
};

/// Every error one build found, in file order; what() has one error per line and a count.
/// Its own file/line/path/message are those of the first error, so a catch of ConfigError that
/// reads them keeps working.
class ConfigErrorList : public ConfigError {
 public:
  explicit ConfigErrorList(std::vector<ConfigError> errors);
  const char* what() const noexcept override { return text_.c_str(); }
  /// The errors, at least one.
  const std::vector<ConfigError>& errors() const { return errors_; }

 private:
  std::vector<ConfigError> errors_;
  std::string text_;
};

/// What `${PLUGSLAM_DATA}` stands for in a config: $PLUGSLAM_DATA, else ../shared/data beside
/// the source tree this host was built from.
std::string dataFolder();
/// Replaces `${PLUGSLAM_DATA}` in every scalar of `node`; any other `${...}` is a ConfigError at
/// its line in `file`. (A config names no other variables, and runs no commands.)
void expandVariables(YAML::Node node, const std::string& file);

/// Reads a YAML file (variables expanded); syntax errors become ConfigError with line and column.
/// A file with `base: OTHER` (a path relative to it; or a list of paths, each written over the
/// one before) starts from OTHER's document, its own base resolved first, and writes its other
/// keys over it: a map without `type:` changes the base's map or module key by key, anything
/// else (a module with its `type:`, a list, a value) replaces what the base had. A key may be a
/// --set path ("tracker.splitter.distance", "outputs[1]"): "[i]" is a list's entry i, and i =
/// the list's length appends one.
ConfigDocument loadConfigFile(const std::string& file);
/// Parses YAML text (tests, the shell) as loadConfigFile does; `name` is used as the file name in
/// errors, and a `base:` is relative to its folder (to the current folder for "<...>" names).
ConfigDocument loadConfigText(const std::string& text, const std::string& name);
/// The file that wrote the value at `path` (doc.sources, else doc.file).
std::string sourceOf(const ConfigDocument& doc, const std::string& path);
/// The document a run uses, as YAML text: what sessions save, `plugslam config --resolved`.
std::string resolvedYaml(const ConfigDocument& doc);
/// Applies "path=value" (value parsed as YAML) to the document, replacing what was there; the
/// path must be well formed, and "[i]" with i = a list's length appends an entry. Errors in the
/// value name `origin`, what the user typed (default "--set path=value").
void applyOverride(ConfigDocument& doc, const std::string& assignment,
                   const std::string& origin = "");
/// Splits "a.b[2].c" into {"a", "b", "[2]", "c"}; throws InputError when malformed.
std::vector<std::string> splitPath(const std::string& path);

/// Builds and configures modules from YAML. Errors are collected: an error in one key or list
/// item is recorded and the build goes on with the next one (the module whose key failed skips
/// its own configure(), so one mistake does not cascade). configure() and configureRoot() throw
/// everything collected (a ConfigError, a ConfigErrorList when there are several) when they
/// return; loadPlugins() and report() only record, for check() or the next configure to throw.
class ConfigBuilder {
 public:
  ConfigBuilder(const ConfigDocument& doc, PluginManager& plugins,
                Registry& registry = Registry::instance());

  /// Loads the plugins listed under `key` (a list of names or paths) of the root map; records
  /// each plugin that fails and goes on.
  void loadPlugins(const std::string& key = "plugins");
  /// Configures `obj` from the map `node` located at `path` (its params, slots, then configure());
  /// throws every error collected so far.
  void configure(Configurable& obj, const YAML::Node& node, const std::string& path);
  /// Configures the root object from the whole document, skipping the listed root keys; throws
  /// every error collected so far.
  void configureRoot(Configurable& root, const std::vector<std::string>& skip_keys = {});
  /// Creates one module for `slot` from `node` (a type name or a map with `type:`).
  std::shared_ptr<Configurable> create(const SlotBase& slot, const YAML::Node& node,
                                       const std::string& path);

  /// Throws a ConfigError located at `node` (or at the --set that produced `path`).
  [[noreturn]] void fail(const YAML::Node& node, const std::string& path,
                         const std::string& message) const;
  /// Records the error fail() would throw, and returns: for checks that go on to the next item.
  void report(const YAML::Node& node, const std::string& path, const std::string& message);
  /// The errors recorded so far, in the order found.
  const std::vector<ConfigError>& errors() const { return errors_; }
  /// Throws the recorded errors (ConfigError for one, ConfigErrorList for several), if any.
  void check() const;

 private:
  ConfigError locate(const YAML::Node& node, const std::string& path,
                     const std::string& message) const;
  std::string where(const YAML::Node& node, const std::string& path) const;  // "file:line:col"
  void configureObject(Configurable& obj, const YAML::Node& node, const std::string& path);
  std::string resolveType(const SlotBase& slot, const std::string& type, const YAML::Node& at,
                          const std::string& path);
  void fillSlot(SlotBase& slot, const YAML::Node& node, const std::string& path);
  const ConfigDocument& doc_;
  PluginManager& plugins_;
  Registry& registry_;
  std::map<std::string, std::string> names_;  // explicit instance name -> where first used
  std::vector<ConfigError> errors_;
  std::map<std::string, std::string> failed_plugins_;  // plugin -> where its load failed
};

/// "an AlignerSlice2D", "a Splitter": a kind or type name with its indefinite article.
std::string withArticle(const std::string& noun);

/// Dumps a configurable's current values (and nested modules) as YAML.
YAML::Node dumpConfig(const Configurable& obj, bool with_type = true);

}  // namespace plugslam::runtime
