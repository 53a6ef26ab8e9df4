#pragma once
// Each parameter is declared once (as PX4 declares its parameters): a FieldTable<S> lists every
// field of a Params struct with its YAML key, default, allowed range, unit and description. The
// same table gives the struct its defaults (apply_defaults), checks it (check_fields, behind
// every Params::validate()), reads and writes YAML (field_table_yaml.hpp) and prints the README
// table and --help-params. Pure: no YAML, no I/O, so core libraries may hold their tables.

#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "common/util/result.hpp"

namespace stereoball::params {

/// What a field holds, as written in YAML.
enum class Kind { kBool, kInt, kReal, kText, kChoice, kList };

/// A field's value whatever its member type: integers as int64, reals as double, lists of reals.
using Value = std::variant<bool, std::int64_t, double, std::string, std::vector<double>>;

/// Allowed values of a number (or of each entry of a list); NaN is never allowed.
struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false;  ///< lo itself is refused: (lo, hi]

  bool contains(double v) const { return (lo_open ? v > lo : v >= lo) && v <= hi; }
  /// "[0.1, 20]", "(0, 1000]"; "any" without bounds.
  std::string text() const;
};

/// Everything about a field but how to reach it in the struct.
struct FieldSpec {
  std::string key;  ///< dotted YAML key ("p2p.min_radius_px")
  Kind kind = Kind::kReal;
  Value fallback;                    ///< the default
  Range range;                       ///< numbers, list entries
  std::string unit;                  ///< "m", "ns", "" (unitless)
  std::string text;                  ///< one-line description
  std::vector<std::string> choices;  ///< kChoice: the allowed words
  std::size_t list_size = 0;         ///< kList: exact length (0 = one or more)
  bool whole_numbers = false;        ///< kList: entries must be integers
  bool optional = false;             ///< may be left out of the file (the default applies)
};

/// A value as YAML and the tables write it: the shortest text that reads back to the same value.
std::string value_text(const Value& v);
/// The allowed values in words: "[0.1, 20]", "grey, red", "true/false", "5 numbers in [-1, 1]".
std::string allowed_text(const FieldSpec& spec);
/// Success if v suits spec (kind, range, choice, list length); else "key 'K': ... ".
Status check_value(const FieldSpec& spec, const Value& v);

/// A field of S: its spec plus how to read and write it in an S.
template <typename S>
struct Field : FieldSpec {
  std::function<Value(const S&)> get;
  std::function<void(S&, const Value&)> set;  ///< v has passed check_value
};

/// Every field of S, plus the rules between fields (min < max...), checked after the ranges.
template <typename S>
struct FieldTable {
  FieldTable(std::vector<Field<S>> f = {}, std::function<Status(const S&)> check = {})
      : fields(std::move(f)), cross_check(std::move(check)) {}
  std::vector<Field<S>> fields;
  std::function<Status(const S&)> cross_check;  ///< may be empty
};

/// How a member type maps to a Value; specialise for other types (e.g. a 3-vector).
template <typename M, typename Enable = void>
struct Codec;

template <>
struct Codec<bool> {
  static constexpr Kind kKind = Kind::kBool;
  static Value to(bool m) { return m; }
  static bool from(const Value& v) { return std::get<bool>(v); }
};

template <typename M>
struct Codec<M, std::enable_if_t<std::is_integral_v<M> && !std::is_same_v<M, bool>>> {
  static constexpr Kind kKind = Kind::kInt;
  static Value to(M m) { return static_cast<std::int64_t>(m); }
  static M from(const Value& v) { return static_cast<M>(std::get<std::int64_t>(v)); }
};

template <typename M>
struct Codec<M, std::enable_if_t<std::is_floating_point_v<M>>> {
  static constexpr Kind kKind = Kind::kReal;
  static Value to(M m) { return static_cast<double>(m); }
  static M from(const Value& v) { return static_cast<M>(std::get<double>(v)); }
};

template <>
struct Codec<std::string> {
  static constexpr Kind kKind = Kind::kText;
  static Value to(const std::string& m) { return m; }
  static std::string from(const Value& v) { return std::get<std::string>(v); }
};

template <typename E>
struct Codec<std::vector<E>, std::enable_if_t<std::is_arithmetic_v<E>>> {
  static constexpr Kind kKind = Kind::kList;
  static constexpr std::size_t kSize = 0;
  static constexpr bool kWhole = std::is_integral_v<E>;
  static Value to(const std::vector<E>& m) { return std::vector<double>(m.begin(), m.end()); }
  static std::vector<E> from(const Value& v) {
    const auto& d = std::get<std::vector<double>>(v);
    std::vector<E> out;
    for (double x : d) out.push_back(static_cast<E>(x));
    return out;
  }
};

template <std::size_t N>
struct Codec<std::array<double, N>> {
  static constexpr Kind kKind = Kind::kList;
  static constexpr std::size_t kSize = N;
  static constexpr bool kWhole = false;
  static Value to(const std::array<double, N>& m) {
    return std::vector<double>(m.begin(), m.end());
  }
  static std::array<double, N> from(const Value& v) {
    std::array<double, N> out{};
    const auto& d = std::get<std::vector<double>>(v);
    for (std::size_t i = 0; i < N && i < d.size(); ++i) out[i] = d[i];
    return out;
  }
};

/// Reaches a member of S, possibly nested: at(&S::p2p, &P2P::min_radius_px).
template <typename S, typename M>
using Access = std::function<M&(S&)>;

template <typename S, typename M>
Access<S, M> at(M S::*m) {
  return [m](S& s) -> M& { return s.*m; };
}
template <typename S, typename A, typename M>
Access<S, M> at(A S::*a, M A::*m) {
  return [a, m](S& s) -> M& { return (s.*a).*m; };
}
template <typename S, typename A, typename B, typename M>
Access<S, M> at(A S::*a, B A::*b, M B::*m) {
  return [a, b, m](S& s) -> M& { return ((s.*a).*b).*m; };
}

namespace detail {

inline FieldSpec spec(std::string key, Kind kind, Value fallback, std::string text) {
  FieldSpec s;
  s.key = std::move(key);
  s.kind = kind;
  s.fallback = std::move(fallback);
  s.text = std::move(text);
  return s;
}

template <typename S, typename M>
Field<S> bind(FieldSpec spec, Access<S, M> access) {
  Field<S> f;
  static_cast<FieldSpec&>(f) = std::move(spec);
  // get() only reads: the const_cast lets one accessor serve both directions.
  f.get = [access](const S& s) { return Codec<M>::to(access(const_cast<S&>(s))); };
  f.set = [access](S& s, const Value& v) { access(s) = Codec<M>::from(v); };
  return f;
}

/// The range narrowed to what the member type can hold, so a checked value always fits.
template <typename M>
Range fit_range(Range r) {
  if constexpr (std::is_integral_v<M>) {
    r.lo = std::max(r.lo, static_cast<double>(std::numeric_limits<M>::lowest()));
    r.hi = std::min(r.hi, static_cast<double>(std::numeric_limits<M>::max()));
  }
  return r;
}

}  // namespace detail

/// A number (integer or real member): key, member, default, allowed range, unit, description.
template <typename S, typename M>
Field<S> number(std::string key, Access<S, M> access, std::type_identity_t<M> fallback, Range range,
                std::string unit, std::string text) {
  static_assert(Codec<M>::kKind == Kind::kInt || Codec<M>::kKind == Kind::kReal);
  FieldSpec s =
      detail::spec(std::move(key), Codec<M>::kKind, Codec<M>::to(fallback), std::move(text));
  s.range = detail::fit_range<M>(range);
  s.unit = std::move(unit);
  return detail::bind<S, M>(std::move(s), std::move(access));
}

/// true/false.
template <typename S>
Field<S> flag(std::string key, Access<S, bool> access, bool fallback, std::string text) {
  return detail::bind<S, bool>(detail::spec(std::move(key), Kind::kBool, fallback, std::move(text)),
                               std::move(access));
}

/// Free text (paths, device names).
template <typename S>
Field<S> text(std::string key, Access<S, std::string> access, std::string fallback,
              std::string text) {
  return detail::bind<S, std::string>(
      detail::spec(std::move(key), Kind::kText, std::move(fallback), std::move(text)),
      std::move(access));
}

/// One word of choices.
template <typename S>
Field<S> choice(std::string key, Access<S, std::string> access, std::string fallback,
                std::vector<std::string> choices, std::string text) {
  FieldSpec s = detail::spec(std::move(key), Kind::kChoice, std::move(fallback), std::move(text));
  s.choices = std::move(choices);
  return detail::bind<S, std::string>(std::move(s), std::move(access));
}

/// An enum written as one word: to_word/from_word convert (from_word only sees listed words).
template <typename S, typename E>
Field<S> choice(std::string key, Access<S, E> access, std::type_identity_t<E> fallback,
                std::vector<std::string> choices, std::string (*to_word)(E),
                E (*from_word)(const std::string&), std::string text) {
  Field<S> f;
  static_cast<FieldSpec&>(f) =
      detail::spec(std::move(key), Kind::kChoice, to_word(fallback), std::move(text));
  f.choices = std::move(choices);
  f.get = [access, to_word](const S& s) { return Value{to_word(access(const_cast<S&>(s)))}; };
  f.set = [access, from_word](S& s, const Value& v) {
    access(s) = from_word(std::get<std::string>(v));
  };
  return f;
}

/// A list of numbers (std::vector or std::array member); each entry in range.
template <typename S, typename M>
Field<S> list(std::string key, Access<S, M> access, std::type_identity_t<M> fallback, Range range,
              std::string unit, std::string text) {
  FieldSpec s = detail::spec(std::move(key), Kind::kList, Codec<M>::to(fallback), std::move(text));
  s.range = range;
  s.unit = std::move(unit);
  s.list_size = Codec<M>::kSize;
  s.whole_numbers = Codec<M>::kWhole;
  return detail::bind<S, M>(std::move(s), std::move(access));
}

/// The same field, allowed to be left out of the file (then its default applies).
template <typename S>
Field<S> optional(Field<S> f) {
  f.optional = true;
  return f;
}

/// The fields of a sub-table, reached through member sub of S, keys prefixed "prefix."
/// (unchanged when prefix is empty); its cross-check runs on the member.
template <typename S, typename Sub>
FieldTable<S> section(const std::string& prefix, Sub S::*sub, const FieldTable<Sub>& table) {
  FieldTable<S> out;
  for (const auto& f : table.fields) {
    Field<S> g;
    static_cast<FieldSpec&>(g) = f;
    if (!prefix.empty()) g.key = prefix + "." + f.key;
    g.get = [sub, get = f.get](const S& s) { return get(s.*sub); };
    g.set = [sub, set = f.set](S& s, const Value& v) { set(s.*sub, v); };
    out.fields.push_back(std::move(g));
  }
  if (table.cross_check) {
    out.cross_check = [sub, check = table.cross_check](const S& s) { return check(s.*sub); };
  }
  return out;
}

/// The table of S, built by make on first use (one table per struct type).
template <typename S>
const FieldTable<S>& table_of(FieldTable<S> (*make)()) {
  static const FieldTable<S> table = make();
  return table;
}

/// Sets every field of s to its default.
template <typename S>
void apply_defaults(const FieldTable<S>& table, S& s) {
  for (const auto& f : table.fields) f.set(s, f.fallback);
}

/// Every field in its range (first failure: "key 'K': ..."), then the cross-field rules.
template <typename S>
Status check_fields(const FieldTable<S>& table, const S& s) {
  for (const auto& f : table.fields) {
    if (auto st = check_value(f, f.get(s)); !st) return st;
  }
  if (table.cross_check) return table.cross_check(s);
  return {};
}

/// The specs of a table, in order (for the text generators).
template <typename S>
std::vector<FieldSpec> specs(const FieldTable<S>& table) {
  return {table.fields.begin(), table.fields.end()};
}

/// The (key, value) pairs of s, in table order.
template <typename S>
std::vector<std::pair<std::string, Value>> values(const FieldTable<S>& table, const S& s) {
  std::vector<std::pair<std::string, Value>> out;
  for (const auto& f : table.fields) out.emplace_back(f.key, f.get(s));
  return out;
}

/// Markdown table of the fields: | key | default | allowed | unit | description |.
std::string markdown_table(const std::vector<FieldSpec>& specs);

/// "key 'K': V is out of range [lo, hi] unit" for a cross-field rule of the caller's own.
std::string out_of_range(const std::string& key, double v, const Range& r, const std::string& unit,
                         const std::string& why = "");

}  // namespace stereoball::params

/// Defines what every Params struct TYPE with a field table needs, in one line: the table's
/// accessor ACCESSOR() (built once by MAKE), TYPE() (every field at its default) and
/// Status TYPE::validate() const (ranges, then the rules between fields).
#define SB_PARAMS_TABLE(TYPE, ACCESSOR, MAKE)                     \
  const ::stereoball::params::FieldTable<TYPE>& ACCESSOR() {      \
    return ::stereoball::params::table_of(MAKE);                  \
  }                                                               \
  TYPE::TYPE() {                                                  \
    ::stereoball::params::apply_defaults(ACCESSOR(), *this);      \
  }                                                               \
  ::stereoball::Status TYPE::validate() const {                   \
    return ::stereoball::params::check_fields(ACCESSOR(), *this); \
  }
