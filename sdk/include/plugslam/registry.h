#pragma once
// The type registry: every configurable type is known by name ("<plugin>.<Type>") with its
// interface kind and a one-line description; the YAML builder creates modules through it.
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "plugslam/configurable.h"
#include "plugslam/pose_space.h"
#include "plugslam/value_types.h"

namespace plugslam {
inline namespace abi_v1 {

/// What the registry knows about one type.
struct TypeInfo {
  std::string name;    ///< full name, "laser2d.PointToLineSlice"
  std::string plugin;  ///< owning plugin ("sdk" for built-ins)
  std::string kind;    ///< interface kind, "AlignerSlice"
  std::string doc;     ///< one-line description
  std::function<Configurable*()> factory;  ///< creates a default-configured instance
  /// The plugin's library; each created object holds it, so the code stays mapped while it lives.
  /// Weak: the plugin manager owns the library while the plugin is loaded.
  std::weak_ptr<void> library;
};

/// Process-wide registry of configurable types.
class Registry {
 public:
  /// The registry, with the SDK's built-in types registered on first use.
  static Registry& instance();

  /// Adds a type; throws InputError if the name is taken.
  void add(TypeInfo info);
  /// The type called `name`, if registered.
  std::optional<TypeInfo> find(const std::string& name) const;
  /// Creates an instance; the object keeps its plugin loaded until it is destroyed.
  /// Throws InputError for an unknown name, with a "did you mean" when one is close.
  std::shared_ptr<Configurable> create(const std::string& name) const;
  /// Every type, sorted by name; only those of `kind` when it is not empty.
  std::vector<TypeInfo> types(const std::string& kind = "") const;
  /// The types registered by one plugin.
  std::vector<TypeInfo> typesOf(const std::string& plugin) const;
  /// Removes every type of a plugin (before it is unloaded).
  void removePlugin(const std::string& plugin);
  /// The registered name closest to `name` within a small edit distance, or "".
  std::string closest(const std::string& name, const std::string& kind = "") const;

 private:
  Registry() = default;
  mutable std::mutex mutex_;
  std::vector<TypeInfo> types_;
};

/// Handed to a plugin's register function: adds its types under "<plugin>.<Type>".
class Registrar {
 public:
  /// Used by the host; `library` keeps the plugin mapped as long as any of its objects lives.
  Registrar(Registry& registry, std::string plugin, std::shared_ptr<void> library);

  /// Registers type T (default-constructible, derived from a module interface) as
  /// "<plugin>.<type>".
  template <class T>
  void add(const std::string& type, const std::string& doc) {
    addFactory(type, T::kKind, doc, []() -> Configurable* { return new T(); });
  }
  /// Registers a module written for both pose spaces, T<Space2D> and T<Space3D>, as
  /// "<plugin>.<type>2D" and "<plugin>.<type>3D" (the suffixes sdk types look their slots up
  /// by); `doc_3d`, when given, is the 3D one's doc.
  template <template <class> class T>
  void addBothSpaces(const std::string& type, const std::string& doc,
                     const std::string& doc_3d = "") {
    add<T<Space2D>>(type + Space2D::kSuffix, doc);
    add<T<Space3D>>(type + Space3D::kSuffix, doc_3d.empty() ? doc : doc_3d);
  }
  /// Registers a serializable value type T (with save/load overloads) as "<plugin>.<tag>", so
  /// containers holding it can be saved and loaded again.
  template <class T>
  void addValueType(const std::string& tag, const std::string& display_name = "") {
    ValueTypes::instance().add<T>(plugin_ + "." + tag, plugin_, display_name);
  }
  /// Name of the plugin being registered.
  const std::string& plugin() const { return plugin_; }
  /// Full names registered so far.
  const std::vector<std::string>& added() const { return added_; }

 private:
  void addFactory(const std::string& type, const char* kind, const std::string& doc,
                  std::function<Configurable*()> factory);
  Registry& registry_;
  std::string plugin_;
  std::shared_ptr<void> library_;
  std::vector<std::string> added_;
};

/// Levenshtein distance, for "did you mean" suggestions.
size_t editDistance(const std::string& a, const std::string& b);
/// The candidate closest to `word`, if within a small distance; "" otherwise.
std::string closestMatch(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace abi_v1
}  // namespace plugslam
