#pragma once
// One table per enum of the names configs, the CLI and reports spell, so naming a value and
// parsing a name cannot drift apart.
#include <cstddef>
#include <optional>
#include <string_view>

namespace plugslam {
inline namespace abi_v1 {

/// A value of enum E and its name.
template <class E>
struct EnumName {
  E value;
  const char* name;
};

/// The name of `value` in `table`, or `fallback` when the table lacks it.
template <class E, std::size_t N>
constexpr const char* enumName(const EnumName<E> (&table)[N], E value, const char* fallback) {
  for (const EnumName<E>& entry : table)
    if (entry.value == value) return entry.name;
  return fallback;
}

/// The value `table` names `name` (compared exactly), if any.
template <class E, std::size_t N>
constexpr std::optional<E> enumValue(const EnumName<E> (&table)[N], std::string_view name) {
  for (const EnumName<E>& entry : table)
    if (name == entry.name) return entry.value;
  return std::nullopt;
}

}  // namespace abi_v1
}  // namespace plugslam
