#pragma once
// The registry of value-type tags. Saving a property writes its tag; loading looks the tag up here
// to recreate the right Property<T>. Plugins add their own types under "<plugin>.<Type>" with the
// plugin as owner, and the host removes them (removeOwner) before it unloads that plugin, because
// each entry's factory is code that lives in the plugin.
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <typeindex>
#include <vector>

#include "plugslam/property.h"

namespace plugslam {
inline namespace abi_v1 {

/// One registered value type.
struct ValueTypeInfo {
  std::string tag;           ///< the name written into archives ("double", "laser2d.Scan")
  std::string display_name;  ///< the name in error messages ("std::vector<Eigen::Vector2d>")
  std::string owner;         ///< "sdk" or the plugin that registered it
  std::type_index type;      ///< the C++ type
  /// Creates a default-valued Property<T> with the given name.
  std::function<std::unique_ptr<PropertyBase>(const std::string& name)> make;
};

/// The process-wide registry of value-type tags; thread-safe.
class ValueTypes {
 public:
  /// The registry, created on first use with the SDK's built-in types (owner "sdk").
  static ValueTypes& instance();

  /// Registers T under `tag` for `owner`. `display_name` defaults to the tag. Re-adding the same
  /// (tag, type, owner) is a no-op; a tag or type already registered otherwise throws InputError.
  template <class T>
  void add(const std::string& tag, const std::string& owner, const std::string& display_name = "") {
    static_assert(kIsSerializable<T>,
                  "a value type needs save(OutArchive&, const T&) and load(InArchive&, T&)");
    static_assert(std::is_default_constructible_v<T>,
                  "a value type must be default-constructible to be loaded");
    addEntry(ValueTypeInfo{tag, display_name.empty() ? tag : display_name, owner,
                           std::type_index(typeid(T)),
                           [](const std::string& name) -> std::unique_ptr<PropertyBase> {
                             return std::make_unique<Property<T>>(name);
                           }});
  }

  /// Registers a prepared entry (what add<T> builds); same rules as add<T>.
  void addEntry(ValueTypeInfo info);
  /// The entry for a tag, if registered.
  std::optional<ValueTypeInfo> findByTag(const std::string& tag) const;
  /// The entry for a C++ type, if registered.
  std::optional<ValueTypeInfo> findByType(const std::type_index& type) const;
  /// The tag of a C++ type, or "" when unregistered.
  std::string tagOf(const std::type_index& type) const;
  /// A new default-valued property for `tag`; throws InputError naming the tag and the plugin
  /// that probably registers it when the tag is unknown.
  std::unique_ptr<PropertyBase> make(const std::string& tag, const std::string& name) const;
  /// Removes every entry of `owner` and returns how many; the SDK's own entries cannot be removed
  /// (InputError).
  std::size_t removeOwner(const std::string& owner);
  /// All registered tags, sorted.
  std::vector<std::string> tags() const;

  /// The message for a tag nobody registered (used by make() and by the archive loaders).
  static std::string unknownTagMessage(const std::string& tag);

 private:
  ValueTypes();
  ValueTypes(const ValueTypes&) = delete;
  ValueTypes& operator=(const ValueTypes&) = delete;

  mutable std::mutex mutex_;
  std::vector<ValueTypeInfo> entries_;  // few dozen entries: linear search is fine
};

}  // namespace abi_v1
}  // namespace plugslam
