#include "plugslam/param.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <limits>
#include <sstream>

#include "plugslam/configurable.h"
#include "plugslam/errors.h"

namespace plugslam {
inline namespace abi_v1 {

namespace {

std::string describeNode(const YAML::Node& node) {
  switch (node.Type()) {
    case YAML::NodeType::Null:
    case YAML::NodeType::Undefined:
      return "nothing";
    case YAML::NodeType::Sequence:
      return "a list";
    case YAML::NodeType::Map:
      return "a map";
    case YAML::NodeType::Scalar:
      return "'" + node.Scalar() + "'";
  }
  return "a value";
}

std::string formatNumber(double v) {
  std::ostringstream s;
  s.precision(15);
  s << v;
  return s.str();
}

// Scalar conversions: strict, so "1.5" is not an int and "yes" is not a bool.
template <class T>
struct Scalar;

template <>
struct Scalar<bool> {
  static std::string name() { return "bool"; }
  static bool parse(const YAML::Node& n) {
    if (n.IsScalar()) {
      const std::string& s = n.Scalar();
      if (s == "true" || s == "True" || s == "TRUE") return true;
      if (s == "false" || s == "False" || s == "FALSE") return false;
    }
    throw ValueError("expected a bool (true or false), got " + describeNode(n));
  }
  static double number(bool) { return 0; }
  static constexpr bool kNumeric = false;
};

template <>
struct Scalar<double> {
  static std::string name() { return "double"; }
  static double parse(const YAML::Node& n) {
    if (n.IsScalar()) {
      const std::string& s = n.Scalar();
      if (s == ".inf" || s == "inf") return std::numeric_limits<double>::infinity();
      if (s == "-.inf" || s == "-inf") return -std::numeric_limits<double>::infinity();
      char* end = nullptr;
      double v = std::strtod(s.c_str(), &end);
      if (!s.empty() && end == s.c_str() + s.size() && !std::isnan(v)) return v;
    }
    throw ValueError("expected a number, got " + describeNode(n));
  }
  static double number(double v) { return v; }
  static constexpr bool kNumeric = true;
};

template <class I>
struct IntScalar {
  static I parse(const YAML::Node& n) {
    if (n.IsScalar()) {
      const std::string& s = n.Scalar();
      char* end = nullptr;
      errno = 0;
      long long v = std::strtoll(s.c_str(), &end, 10);
      if (!s.empty() && end == s.c_str() + s.size() && errno == 0 &&
          v >= std::numeric_limits<I>::min() && v <= std::numeric_limits<I>::max())
        return static_cast<I>(v);
    }
    throw ValueError("expected an integer, got " + describeNode(n));
  }
  static double number(I v) { return static_cast<double>(v); }
  static constexpr bool kNumeric = true;
};
template <>
struct Scalar<int> : IntScalar<int> {
  static std::string name() { return "int"; }
};
template <>
struct Scalar<int64_t> : IntScalar<int64_t> {
  static std::string name() { return "int64"; }
};

template <>
struct Scalar<std::string> {
  static std::string name() { return "string"; }
  static std::string parse(const YAML::Node& n) {
    if (n.IsScalar()) return n.Scalar();
    throw ValueError("expected a string, got " + describeNode(n));
  }
  static double number(const std::string&) { return 0; }
  static constexpr bool kNumeric = false;
};

template <class T>
struct Codec {
  using S = Scalar<T>;
  static std::string name() { return S::name(); }
  static T parse(const YAML::Node& n) { return S::parse(n); }
  static YAML::Node emit(const T& v) {
    if constexpr (std::is_same_v<T, double>) {
      return YAML::Node(formatNumber(v));
    } else if constexpr (std::is_same_v<T, bool>) {
      return YAML::Node(v ? "true" : "false");
    } else {
      return YAML::Node(v);
    }
  }
};

template <class E>
struct Codec<std::vector<E>> {
  static std::string name() { return "list<" + Scalar<E>::name() + ">"; }
  static std::vector<E> parse(const YAML::Node& n) {
    if (!n.IsSequence())
      throw ValueError("expected a list of " + Scalar<E>::name() + ", got " + describeNode(n));
    std::vector<E> out;
    out.reserve(n.size());
    for (size_t i = 0; i < n.size(); ++i) {
      try {
        out.push_back(Scalar<E>::parse(n[i]));
      } catch (const ValueError& e) {
        throw ValueError("element " + std::to_string(i) + ": " + e.what());
      }
    }
    return out;
  }
  static YAML::Node emit(const std::vector<E>& v) {
    YAML::Node seq(YAML::NodeType::Sequence);
    for (const auto& e : v) seq.push_back(Codec<E>::emit(e));
    seq.SetStyle(YAML::EmitterStyle::Flow);
    return seq;
  }
};

template <class T>
void forEachNumber(const T& v, const std::function<void(double)>& f) {
  if constexpr (Scalar<T>::kNumeric) f(Scalar<T>::number(v));
}
template <class E>
void forEachNumber(const std::vector<E>& v, const std::function<void(double)>& f) {
  if constexpr (Scalar<E>::kNumeric)
    for (const auto& e : v) f(Scalar<E>::number(e));
}
template <class T>
void forEachString(const T& v, const std::function<void(const std::string&)>& f) {
  if constexpr (std::is_same_v<T, std::string>) f(v);
}
template <class E>
void forEachString(const std::vector<E>& v, const std::function<void(const std::string&)>& f) {
  if constexpr (std::is_same_v<E, std::string>)
    for (const auto& e : v) f(e);
}

std::string compactYaml(const YAML::Node& n) {
  YAML::Emitter out;
  out.SetMapFormat(YAML::Flow);
  out.SetSeqFormat(YAML::Flow);
  out << n;
  return out.c_str();
}

}  // namespace

ParamBase::ParamBase(Configurable* owner, std::string name, std::string unit, std::string doc,
                     std::optional<Range> range, std::vector<std::string> choices)
    : name_(std::move(name)),
      unit_(std::move(unit)),
      doc_(std::move(doc)),
      range_(range),
      choices_(std::move(choices)) {
  if (owner) owner->params_.push_back(this);
}

ParamBase::~ParamBase() = default;

std::string ParamBase::valueText() const { return compactYaml(toYaml()); }
std::string ParamBase::defaultText() const { return compactYaml(defaultYaml()); }

void ParamBase::checkRange(double v) const {
  if (range_ && (v < range_->min || v > range_->max))
    throw ValueError("value " + formatNumber(v) + " is out of range [" + formatNumber(range_->min) +
                     ", " + formatNumber(range_->max) + "]");
}

void ParamBase::checkChoice(const std::string& v) const {
  if (choices_.empty()) return;
  for (const auto& c : choices_)
    if (c == v) return;
  std::string list;
  for (const auto& c : choices_) list += (list.empty() ? "" : ", ") + c;
  throw ValueError("'" + v + "' is not one of: " + list);
}

template <class T>
void Param<T>::check(const T& v) const {
  forEachNumber(v, [this](double x) { checkRange(x); });
  forEachString(v, [this](const std::string& s) { checkChoice(s); });
}

template <class T>
void Param<T>::set(const T& v) {
  check(v);
  value_ = v;
  markSet();
}

template <class T>
std::string Param<T>::typeName() const {
  return Codec<T>::name();
}

template <class T>
YAML::Node Param<T>::toYaml() const {
  return Codec<T>::emit(value_);
}

template <class T>
YAML::Node Param<T>::defaultYaml() const {
  return Codec<T>::emit(default_);
}

template <class T>
void Param<T>::fromYaml(const YAML::Node& node) {
  set(Codec<T>::parse(node));
}

template class Param<bool>;
template class Param<int>;
template class Param<int64_t>;
template class Param<double>;
template class Param<std::string>;
template class Param<std::vector<int>>;
template class Param<std::vector<double>>;
template class Param<std::vector<std::string>>;

}  // namespace abi_v1
}  // namespace plugslam
