#pragma once
// Entries: a module's typed bindings to named properties of a time step's containers. An entry is
// a string parameter (its YAML key names the property: `measurement: front`) that also says which
// container the property lives in, its value type, and whether the module reads or writes it, so
// a pipeline's wiring is checked before the first frame and `plugslam describe` shows it:
//   Input<PointCloud2D> measurement{this, Container::measurement, "measurement", "front",
//                                   "cloud to align"};
//   Output<PointCloud2D> output{this, Container::measurement, "output", "front", "cloud"};
// A preprocessor reads and writes through the frame (`input.find(frame)`, `output.emplace(frame)`);
// the SDK binds a slice's entries before it calls the slice, so a slice never sees the frame.
#include <string>
#include <typeindex>
#include <utility>

#include "plugslam/frame.h"
#include "plugslam/param.h"
#include "plugslam/property_container.h"

namespace plugslam {
inline namespace abi_v1 {

class Configurable;

/// The container an entry names a property of.
enum class Container {
  raw,          ///< Frame::raw: the source's readings
  measurement,  ///< Frame::measurement: the preprocessors' cues
  scene,        ///< a local map's scene: the tracker slices' merged cues
};

/// "raw", "measurement" or "scene".
const char* containerName(Container container);

/// Type-erased face of an entry: what the builder checks and introspection shows.
class EntryBase {
 public:
  EntryBase(const EntryBase&) = delete;
  EntryBase& operator=(const EntryBase&) = delete;
  virtual ~EntryBase();

  /// The YAML key: the name of the parameter that holds the property's name.
  const std::string& key() const { return param_.name(); }
  /// The property's name in its container (the parameter's value).
  const std::string& name() const { return param_.value(); }
  /// One-line description.
  const std::string& doc() const { return param_.doc(); }
  /// The container the property lives in.
  Container container() const { return container_; }
  /// True for an Output (the module writes the property), false for an Input.
  bool writes() const { return writes_; }
  /// The value type.
  const std::type_index& type() const { return type_; }
  /// The value type's display name ("laser2d.PointCloud2D"; see typeDisplayName).
  std::string typeName() const;
  /// "reads measurement entry 'front' (laser2d.PointCloud2D)": for messages.
  std::string describe() const;
  /// The parameter that holds the property's name.
  Param<std::string>& param() { return param_; }
  /// The parameter that holds the property's name.
  const Param<std::string>& param() const { return param_; }

  /// Binds to `container` for reading: an Input then points at the property, or at nothing when
  /// it is absent (or `container` is nullptr). PropertyTypeMismatch when it holds another type;
  /// InputError for an Output, which needs a container it may write.
  virtual void bind(const PropertyContainer* container) = 0;
  /// Binds to `container` for reading and writing (an Output writes there).
  virtual void bind(PropertyContainer* container) = 0;
  /// An Input: its property was present at the last bind. An Output: it has a container.
  virtual bool bound() const = 0;

 protected:
  /// Declares the entry on `owner` (normally `this`), with the parameter `key` = `default_name`.
  EntryBase(Configurable* owner, Container container, bool writes, std::type_index type,
            std::string key, std::string default_name, std::string doc);
  /// The frame's container for this entry (raw or measurement); InputError for a scene entry.
  const PropertyContainer& in(const Frame& frame) const;
  /// The frame's container for this entry (raw or measurement); InputError for a scene entry.
  PropertyContainer& in(Frame& frame) const;
  /// Throws the InputError for an Output bound to a read-only container.
  [[noreturn]] void throwReadOnly() const;

 private:
  Param<std::string> param_;
  Container container_;
  bool writes_;
  std::type_index type_;
};

/// A property the module reads: a T in its container, under the configured name.
template <class T>
class Input final : public EntryBase {
 public:
  /// Declares the input on `owner`: YAML key `key`, property name `default_name` by default.
  Input(Configurable* owner, Container container, std::string key, std::string default_name,
        std::string doc)
      : EntryBase(owner, container, false, std::type_index(typeid(T)), std::move(key),
                  std::move(default_name), std::move(doc)) {}
  /// Names the property (as setting the parameter does).
  Input& operator=(const std::string& name) {
    param() = name;
    return *this;
  }

  /// The value found at the last bind, or nullptr when it was absent (valid until the container
  /// changes or the next bind).
  const T* get() const { return value_; }
  /// The bound value (bound() must be true).
  const T& operator*() const { return *value_; }
  /// The bound value (bound() must be true).
  const T* operator->() const { return value_; }
  /// The value in `container`, or nullptr when absent; PropertyTypeMismatch for another type.
  const T* find(const PropertyContainer& container) const { return container.find<T>(name()); }
  /// The value in the frame (its raw or measurement container, as declared), or nullptr.
  const T* find(const Frame& frame) const { return find(in(frame)); }

  void bind(const PropertyContainer* container) override {
    value_ = container ? container->find<T>(name()) : nullptr;
  }
  void bind(PropertyContainer* container) override {
    bind(static_cast<const PropertyContainer*>(container));
  }
  bool bound() const override { return value_ != nullptr; }

 private:
  const T* value_ = nullptr;
};

/// A property the module writes: a T in its container, under the configured name.
template <class T>
class Output final : public EntryBase {
 public:
  /// Declares the output on `owner`: YAML key `key`, property name `default_name` by default.
  Output(Configurable* owner, Container container, std::string key, std::string default_name,
         std::string doc)
      : EntryBase(owner, container, true, std::type_index(typeid(T)), std::move(key),
                  std::move(default_name), std::move(doc)) {}
  /// Names the property (as setting the parameter does).
  Output& operator=(const std::string& name) {
    param() = name;
    return *this;
  }

  /// The value in the bound container, or nullptr when absent (or unbound).
  T* get() const { return container_ ? container_->find<T>(name()) : nullptr; }
  /// The value in the bound container, inserted default-constructed when absent.
  T& getOrInsert() const {
    if (T* value = get()) return *value;
    return container_->set<T>(name(), T{});
  }
  /// Stores `value` in `container` (see PropertyContainer::set).
  T& set(PropertyContainer& container, T value) const {
    return container.set<T>(name(), std::move(value));
  }
  /// Stores `value` in the frame (its raw or measurement container, as declared).
  T& set(Frame& frame, T value) const { return set(in(frame), std::move(value)); }
  /// Constructs the value in `container` from `args` (see PropertyContainer::emplace).
  template <class... Args>
  T& emplace(PropertyContainer& container, Args&&... args) const {
    return container.emplace<T>(name(), std::forward<Args>(args)...);
  }
  /// Constructs the value in the frame (its raw or measurement container, as declared).
  template <class... Args>
  T& emplace(Frame& frame, Args&&... args) const {
    return emplace(in(frame), std::forward<Args>(args)...);
  }

  void bind(const PropertyContainer*) override { throwReadOnly(); }
  void bind(PropertyContainer* container) override { container_ = container; }
  bool bound() const override { return container_ != nullptr; }

 private:
  PropertyContainer* container_ = nullptr;
};

}  // namespace abi_v1
}  // namespace plugslam
