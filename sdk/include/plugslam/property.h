#pragma once
// A property is a named, typed, serializable value (the paper's "Property"). Property<T> holds a
// T by value; PropertyBase is what a PropertyContainer stores and what the archives see.
#include <memory>
#include <string>
#include <type_traits>
#include <typeindex>
#include <typeinfo>
#include <utility>

#include "plugslam/archive.h"
#include "plugslam/errors.h"

namespace plugslam {
inline namespace abi_v1 {

/// The human-readable name of a type: the registered display name or tag when the type is in
/// ValueTypes ("double", "std::vector<Eigen::Vector2d>", "laser2d.Scan"), else the demangled name.
std::string typeDisplayName(const std::type_index& type);

/// typeDisplayName for a static type.
template <class T>
std::string typeName() {
  return typeDisplayName(std::type_index(typeid(T)));
}

/// A named value of some type; the type-erased face of Property<T>.
class PropertyBase {
 public:
  /// A property called `name`.
  explicit PropertyBase(std::string name) : name_(std::move(name)) {}
  virtual ~PropertyBase();
  PropertyBase& operator=(const PropertyBase&) = delete;

  /// The property's name (its key in a container).
  const std::string& name() const { return name_; }
  /// The C++ type of the held value.
  virtual std::type_index type() const = 0;
  /// The human-readable type name (see typeDisplayName).
  std::string typeName() const;
  /// The value-type tag this type is registered under in ValueTypes, or "" when unregistered.
  std::string tag() const;
  /// A deep copy, same name and value. Throws plugslam::Error when the value is not copyable.
  virtual std::unique_ptr<PropertyBase> clone() const = 0;
  /// True when the value type has save/load overloads.
  virtual bool serializable() const = 0;
  /// Writes the value (not the name or tag) into the archive's current slot.
  virtual void saveValue(OutArchive& ar) const = 0;
  /// Reads the value from the archive's current slot.
  virtual void loadValue(InArchive& ar) = 0;

 protected:
  PropertyBase(const PropertyBase&) = default;

 private:
  std::string name_;
};

namespace detail {
/// Throws the error for saving or loading a value type that has no save/load overloads.
[[noreturn]] void throwNotSerializable(const std::string& property, const std::type_index& type);
/// Throws the error for cloning a value type that cannot be copied.
[[noreturn]] void throwNotCopyable(const std::string& property, const std::type_index& type);
}  // namespace detail

/// A property holding a T. T must be default-constructible to be loaded from an archive.
template <class T>
class Property final : public PropertyBase {
 public:
  static_assert(!std::is_reference_v<T> && !std::is_const_v<T>, "Property<T> holds a plain T");

  /// A property called `name` whose value is constructed from `args`.
  template <class... Args>
  explicit Property(std::string name, Args&&... args)
      : PropertyBase(std::move(name)), value_(std::forward<Args>(args)...) {}

  /// The value.
  T& value() { return value_; }
  /// The value.
  const T& value() const { return value_; }

  std::type_index type() const override { return std::type_index(typeid(T)); }

  std::unique_ptr<PropertyBase> clone() const override {
    if constexpr (std::is_copy_constructible_v<T>) {
      return std::unique_ptr<PropertyBase>(new Property<T>(*this));
    } else {
      detail::throwNotCopyable(name(), type());
    }
  }

  bool serializable() const override { return kIsSerializable<T>; }

  void saveValue(OutArchive& ar) const override {
    if constexpr (kIsSerializable<T>) {
      detail::callSave(ar, value_);
    } else {
      detail::throwNotSerializable(name(), type());
    }
  }

  void loadValue(InArchive& ar) override {
    if constexpr (kIsSerializable<T>) {
      detail::callLoad(ar, value_);
    } else {
      detail::throwNotSerializable(name(), type());
    }
  }

 private:
  Property(const Property&) = default;

  T value_;
};

// The built-in value types are instantiated once in the SDK (property.cpp).
extern template class Property<bool>;
extern template class Property<std::int32_t>;
extern template class Property<std::int64_t>;
extern template class Property<std::uint64_t>;
extern template class Property<double>;
extern template class Property<std::string>;
extern template class Property<std::vector<double>>;
extern template class Property<std::vector<std::int64_t>>;
extern template class Property<std::vector<std::string>>;
extern template class Property<std::map<std::string, double>>;
extern template class Property<std::map<std::string, std::string>>;
extern template class Property<Eigen::Vector2d>;
extern template class Property<Eigen::Vector3d>;
extern template class Property<Eigen::Vector4d>;
extern template class Property<Eigen::Matrix2d>;
extern template class Property<Eigen::Matrix3d>;
extern template class Property<Eigen::Matrix4d>;
extern template class Property<Eigen::Matrix<double, 6, 6>>;
extern template class Property<Eigen::VectorXd>;
extern template class Property<Eigen::MatrixXd>;
extern template class Property<Eigen::Isometry2d>;
extern template class Property<Eigen::Isometry3d>;
extern template class Property<std::vector<Eigen::Vector2d>>;
extern template class Property<std::vector<Eigen::Vector3d>>;

}  // namespace abi_v1
}  // namespace plugslam
