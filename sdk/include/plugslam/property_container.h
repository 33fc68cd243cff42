#pragma once
// The dynamic property container: named, typed values kept in insertion order. It is the unit of
// data that flows between modules (raw readings, measurements, scene) and that archives save.
#include <cstddef>
#include <iterator>
#include <memory>
#include <string>
#include <typeindex>
#include <unordered_map>
#include <utility>
#include <vector>

#include "plugslam/errors.h"
#include "plugslam/property.h"

namespace plugslam {
inline namespace abi_v1 {

/// Named, typed values in insertion order; deep-copyable and movable.
class PropertyContainer {
  using Storage = std::vector<std::unique_ptr<PropertyBase>>;

  /// Iterates the properties, dereferencing to PropertyBase& (const or not).
  template <class Base, class It>
  class Iter {
   public:
    using iterator_category = std::forward_iterator_tag;
    using value_type = PropertyBase;
    using difference_type = std::ptrdiff_t;
    using pointer = Base*;
    using reference = Base&;
    Iter() = default;
    explicit Iter(It it) : it_(it) {}
    reference operator*() const { return **it_; }
    pointer operator->() const { return it_->get(); }
    Iter& operator++() {
      ++it_;
      return *this;
    }
    Iter operator++(int) {
      Iter old = *this;
      ++it_;
      return old;
    }
    bool operator==(const Iter& o) const { return it_ == o.it_; }
    bool operator!=(const Iter& o) const { return it_ != o.it_; }

   private:
    It it_{};
  };

 public:
  /// Mutable iteration over the properties in insertion order.
  using iterator = Iter<PropertyBase, Storage::const_iterator>;
  /// Read-only iteration over the properties in insertion order.
  using const_iterator = Iter<const PropertyBase, Storage::const_iterator>;

  /// An empty container.
  PropertyContainer();
  /// A deep copy (every property cloned).
  PropertyContainer(const PropertyContainer& other);
  /// Moves the properties.
  PropertyContainer(PropertyContainer&& other) noexcept;
  /// Deep-copy assignment.
  PropertyContainer& operator=(const PropertyContainer& other);
  /// Move assignment.
  PropertyContainer& operator=(PropertyContainer&& other) noexcept;
  ~PropertyContainer();

  /// A deep copy on the heap.
  std::unique_ptr<PropertyContainer> clone() const;

  /// The value of `name`; PropertyNotFound if absent, PropertyTypeMismatch if it is not a T.
  template <class T>
  T& get(const std::string& name) {
    return checked<T>(at(name)).value();
  }
  /// The value of `name`; PropertyNotFound if absent, PropertyTypeMismatch if it is not a T.
  template <class T>
  const T& get(const std::string& name) const {
    return checked<T>(at(name)).value();
  }
  /// The value of `name`, or nullptr when absent; PropertyTypeMismatch if it is not a T.
  template <class T>
  T* find(const std::string& name) {
    PropertyBase* p = property(name);
    return p ? &checked<T>(*p).value() : nullptr;
  }
  /// The value of `name`, or nullptr when absent; PropertyTypeMismatch if it is not a T.
  template <class T>
  const T* find(const std::string& name) const {
    const PropertyBase* p = property(name);
    return p ? &checked<T>(*p).value() : nullptr;
  }
  /// Inserts `name` at the end or assigns the existing value (which must be a T:
  /// PropertyTypeMismatch otherwise). Returns the stored value.
  template <class T>
  T& set(const std::string& name, T value) {
    if (PropertyBase* p = property(name)) return checked<T>(*p).value() = std::move(value);
    return insertNew<T>(name, std::move(value));
  }
  /// Stores a string literal as a std::string (not as a const char*).
  std::string& set(const std::string& name, const char* value) {
    return set<std::string>(name, std::string(value));
  }
  /// Constructs a T from `args` under `name`: appended when new, replacing the existing value in
  /// place otherwise (which must be a T: PropertyTypeMismatch). Returns the stored value.
  template <class T, class... Args>
  T& emplace(const std::string& name, Args&&... args) {
    if (PropertyBase* p = property(name)) {
      checked<T>(*p);
      replace(std::make_unique<Property<T>>(name, std::forward<Args>(args)...));
      return static_cast<Property<T>&>(at(name)).value();
    }
    return insertNew<T>(name, std::forward<Args>(args)...);
  }

  /// Adds a prepared property, replacing one of the same name whatever its type (used by loaders
  /// and for values whose type is only known at run time). Returns it.
  PropertyBase& add(std::unique_ptr<PropertyBase> property);
  /// The property `name`; PropertyNotFound if absent.
  PropertyBase& at(const std::string& name);
  /// The property `name`; PropertyNotFound if absent.
  const PropertyBase& at(const std::string& name) const;
  /// The property `name`, or nullptr when absent.
  PropertyBase* property(const std::string& name);
  /// The property `name`, or nullptr when absent.
  const PropertyBase* property(const std::string& name) const;

  /// True when `name` is present.
  bool has(const std::string& name) const;
  /// True when `name` is present and holds a T.
  template <class T>
  bool holds(const std::string& name) const {
    const PropertyBase* p = property(name);
    return p && p->type() == std::type_index(typeid(T));
  }
  /// Removes `name`; returns false when it was absent.
  bool erase(const std::string& name);
  /// Removes every property.
  void clear();
  /// The names in insertion order.
  std::vector<std::string> names() const;
  /// The number of properties.
  std::size_t size() const { return properties_.size(); }
  /// True when there are no properties.
  bool empty() const { return properties_.empty(); }

  /// First property in insertion order.
  iterator begin() { return iterator(properties_.begin()); }
  /// Past the last property.
  iterator end() { return iterator(properties_.end()); }
  /// First property in insertion order.
  const_iterator begin() const { return const_iterator(properties_.begin()); }
  /// Past the last property.
  const_iterator end() const { return const_iterator(properties_.end()); }

 private:
  template <class T>
  Property<T>& checked(PropertyBase& p) const {
    if (p.type() != std::type_index(typeid(T))) throwMismatch(p, std::type_index(typeid(T)));
    return static_cast<Property<T>&>(p);
  }
  template <class T>
  const Property<T>& checked(const PropertyBase& p) const {
    if (p.type() != std::type_index(typeid(T))) throwMismatch(p, std::type_index(typeid(T)));
    return static_cast<const Property<T>&>(p);
  }
  template <class T, class... Args>
  T& insertNew(const std::string& name, Args&&... args) {
    auto p = std::make_unique<Property<T>>(name, std::forward<Args>(args)...);
    T& v = p->value();
    append(std::move(p));
    return v;
  }
  [[noreturn]] void throwMismatch(const PropertyBase& p, const std::type_index& requested) const;
  void append(std::unique_ptr<PropertyBase> p);
  void replace(std::unique_ptr<PropertyBase> p);
  void reindex();

  Storage properties_;
  std::unordered_map<std::string, std::size_t> index_;
};

/// Serializes a container: an object with one field per property, in insertion order, each
/// {type: <tag>, value: <value>}. Throws plugslam::Error for a property whose type has no tag.
void save(OutArchive& ar, const PropertyContainer& container);
/// Replaces the container's contents with what the archive holds; an unknown tag throws
/// ParseError naming the tag and the plugin that probably provides it.
void load(InArchive& ar, PropertyContainer& container);

extern template class Property<PropertyContainer>;

}  // namespace abi_v1
}  // namespace plugslam
