#pragma once
// Parameters: named, typed, documented values that a Configurable declares as plain members,
//   Param<double> max_distance{this, "max_distance", 0.5, "m", "max association distance",
//                              Range{0.0, 10.0}};
// and that the YAML builder, `plugslam describe` and the config reference read back.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace YAML {
class Node;
}

namespace plugslam {
inline namespace abi_v1 {

class Configurable;

/// Inclusive bounds of a numeric parameter (applies to every element of a list).
struct Range {
  double min;
  double max;
};

/// The allowed values of a string parameter.
struct Choices {
  std::vector<std::string> values;
};

/// Type-erased view of a parameter, used by introspection, the builder and the docs.
class ParamBase {
 public:
  ParamBase(const ParamBase&) = delete;
  ParamBase& operator=(const ParamBase&) = delete;
  virtual ~ParamBase();

  /// Key of the parameter in YAML.
  const std::string& name() const { return name_; }
  /// Unit ("m", "rad", "Hz"), empty when dimensionless.
  const std::string& unit() const { return unit_; }
  /// One-line description.
  const std::string& doc() const { return doc_; }
  /// Bounds, if any.
  const std::optional<Range>& range() const { return range_; }
  /// Allowed values of a string parameter, empty when free.
  const std::vector<std::string>& choices() const { return choices_; }
  /// True once a value was assigned by configuration (not the default).
  bool isSet() const { return set_; }

  /// Human-readable type: "double", "int", "bool", "string", "list<double>", ...
  virtual std::string typeName() const = 0;
  /// The current value as YAML.
  virtual YAML::Node toYaml() const = 0;
  /// The default value as YAML.
  virtual YAML::Node defaultYaml() const = 0;
  /// Assigns from YAML; throws ValueError saying what was expected.
  virtual void fromYaml(const YAML::Node& node) = 0;
  /// Restores the default value.
  virtual void reset() = 0;
  /// Current value rendered as compact YAML text ("0.5", "[1, 2]").
  std::string valueText() const;
  /// Default value rendered as compact YAML text.
  std::string defaultText() const;

 protected:
  ParamBase(Configurable* owner, std::string name, std::string unit, std::string doc,
            std::optional<Range> range, std::vector<std::string> choices);
  void checkRange(double v) const;
  void checkChoice(const std::string& v) const;
  void markSet() { set_ = true; }
  void clearSet() { set_ = false; }

 private:
  std::string name_, unit_, doc_;
  std::optional<Range> range_;
  std::vector<std::string> choices_;
  bool set_ = false;
};

/// A parameter of value type T. Supported T: bool, int, int64_t, double, std::string and
/// std::vector of int, double or std::string (instantiated once in the SDK).
template <class T>
class Param final : public ParamBase {
 public:
  /// Declares the parameter on `owner` (normally `this`).
  Param(Configurable* owner, std::string name, T default_value, std::string unit, std::string doc)
      : ParamBase(owner, std::move(name), std::move(unit), std::move(doc), std::nullopt, {}),
        default_(default_value),
        value_(std::move(default_value)) {}
  /// Declares a numeric parameter with bounds.
  Param(Configurable* owner, std::string name, T default_value, std::string unit, std::string doc,
        Range range)
      : ParamBase(owner, std::move(name), std::move(unit), std::move(doc), range, {}),
        default_(default_value),
        value_(std::move(default_value)) {}
  /// Declares a string parameter restricted to a set of values.
  Param(Configurable* owner, std::string name, T default_value, std::string unit, std::string doc,
        Choices choices)
      : ParamBase(owner, std::move(name), std::move(unit), std::move(doc), std::nullopt,
                  std::move(choices.values)),
        default_(default_value),
        value_(std::move(default_value)) {}

  /// The current value.
  const T& value() const { return value_; }
  /// The current value (shorthand).
  const T& operator()() const { return value_; }
  /// Implicit read access, so a Param<double> reads like a double.
  operator const T&() const { return value_; }
  /// The default value.
  const T& defaultValue() const { return default_; }
  /// Assigns with the same checks as configuration (range, choices); throws ValueError.
  void set(const T& v);
  /// Assigns and returns *this.
  Param& operator=(const T& v) {
    set(v);
    return *this;
  }

  std::string typeName() const override;
  YAML::Node toYaml() const override;
  YAML::Node defaultYaml() const override;
  void fromYaml(const YAML::Node& node) override;
  void reset() override {
    value_ = default_;
    clearSet();
  }

 private:
  void check(const T& v) const;
  T default_;
  T value_;
};

extern template class Param<bool>;
extern template class Param<int>;
extern template class Param<int64_t>;
extern template class Param<double>;
extern template class Param<std::string>;
extern template class Param<std::vector<int>>;
extern template class Param<std::vector<double>>;
extern template class Param<std::vector<std::string>>;

}  // namespace abi_v1
}  // namespace plugslam
