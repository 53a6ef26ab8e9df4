#pragma once
// One table of {value, name} per enum instead of a hand-written switch: name_of() prints a
// value, value_of() parses a name. A table is a constexpr array beside the enum's to_string():
//   constexpr util::EnumName<Side> kSideNames[] = {{Side::kLeft, "left"}, {Side::kRight, "right"}};
//   std::string_view to_string(Side s) { return util::name_of(kSideNames, s); }

#include <cstddef>
#include <optional>
#include <string_view>

namespace stereoball::util {

/// One row of an enum's name table.
template <typename E>
struct EnumName {
  E value;
  std::string_view name;
};

/// The name of value in table, or nullopt if the table lacks it (an out-of-range value).
template <typename E, std::size_t N>
constexpr std::optional<std::string_view> find_name(const EnumName<E> (&table)[N], E value) {
  for (const auto& row : table) {
    if (row.value == value) return row.name;
  }
  return std::nullopt;
}

/// The name of value in table, or fallback if the table lacks it.
template <typename E, std::size_t N>
constexpr std::string_view name_of(const EnumName<E> (&table)[N], E value,
                                   std::string_view fallback = "unknown") {
  return find_name(table, value).value_or(fallback);
}

/// The value named name (exact, case-sensitive), or nullopt if no row has that name.
template <typename E, std::size_t N>
constexpr std::optional<E> value_of(const EnumName<E> (&table)[N], std::string_view name) {
  for (const auto& row : table) {
    if (row.name == name) return row.value;
  }
  return std::nullopt;
}

}  // namespace stereoball::util
