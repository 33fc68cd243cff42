#pragma once
// The configuration editor behind the built-in page: the registry's introspection (every type's
// parameters with type, default, unit, range and doc), a config as a tree of configurables and
// back to YAML, validation with the CLI's own messages, and saving confined to one folder.
// The viewer server offers these as services ("editor.schema", ...); nothing here touches a
// running pipeline, so a call may run on any thread at any time.
#include <filesystem>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

namespace plugslam::runtime::editor {

/// Every registered type as JSON: name, kind, plugin, doc, params (name, type, default, unit,
/// doc, min/max, choices) and slots (name, kind, list, default type, doc); plus "root", the
/// top level of a run config (plugins, source, pipeline, outputs, ...).
nlohmann::json schemaJson();

/// A config (YAML text) as the editor's tree: each module {type, name, params: [{key, value}],
/// slots: [{key, kind, list, items: [module]}]}, values as YAML text, keys in written order.
/// Throws ConfigError (file, line) on a YAML syntax error.
nlohmann::json treeFromYaml(const std::string& text, const std::string& name);
/// The tree back to YAML text; throws InputError naming the node when the tree is malformed.
std::string treeToYaml(const nlohmann::json& tree);

/// Result of `plugslam validate` on a text.
struct Validation {
  bool ok = false;
  std::vector<std::string> messages;  ///< the CLI's lines (OK line, or one error a line)
};
/// Runs `plugslam validate` (`program`; default: this executable, which must then be plugslam) on
/// the text in a private temporary folder; messages name the file as `shown_name`.
Validation validateYaml(const std::string& text, const std::string& shown_name,
                        const std::string& program = "");

/// The file `relative` under `root`, refusing with InputError: an empty or absolute path, any
/// ".." component, a name not ending in .yaml or .yml, and any path whose existing part
/// (symlinks followed) leads outside root.
std::filesystem::path confinedPath(const std::filesystem::path& root, const std::string& relative);

/// Where the host's editor may save: set by `--root` (default: the folder the host started in).
void setEditorRoot(const std::filesystem::path& root);
/// The editor's folder (the current folder when none was set).
std::filesystem::path editorRoot();

/// The editor of one host: the folder it may write in and the config it runs.
class ConfigEditor {
 public:
  /// `root`: where saves go (must exist); `config_yaml`, `config_name`: the host's config;
  /// `program`: the plugslam executable that validates (default: this one).
  ConfigEditor(std::filesystem::path root, std::string config_yaml, std::string config_name,
               std::string program = "");

  /// Names of the services offered, "editor.*".
  static std::vector<std::string> serviceNames();
  /// True when `service` is one of them.
  static bool handles(const std::string& service);
  /// Answers a service call (JSON request text -> JSON response text); throws InputError with
  /// the reason when the request is refused.
  std::string call(const std::string& service, const std::string& request) const;

  /// The folder saves are confined to (canonical).
  const std::filesystem::path& root() const { return root_; }

 private:
  std::string answer(const std::string& service, const std::string& request) const;

  std::filesystem::path root_;
  std::string config_yaml_, config_name_, program_;
};

}  // namespace plugslam::runtime::editor
