#pragma once
// The checks every field table must pass (for the component tests, GoogleTest): the shipped file
// equals the defaults, every key round-trips YAML -> struct -> YAML, out-of-range values,
// missing, unknown and duplicated keys are refused naming file and key, and a README holds the
// table's generated markdown.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "common/params/field_table_yaml.hpp"

namespace stereoball::params::testing {

using Values = std::vector<std::pair<std::string, Value>>;

inline std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

inline bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

/// An allowed value other than v (nullopt if the field allows only v).
inline std::optional<Value> other_value(const FieldSpec& f, const Value& v) {
  auto other_number = [&](double x) -> std::optional<double> {
    for (double c : {f.range.hi, f.range.lo, x + 1.0, x - 1.0, x / 2.0}) {
      if (std::isfinite(c) && std::fabs(c) < 1e15 && c != x && f.range.contains(c) &&
          (!f.whole_numbers || c == std::floor(c)) &&
          (f.kind != Kind::kInt || c == std::floor(c))) {
        return c;
      }
    }
    return std::nullopt;
  };
  switch (f.kind) {
    case Kind::kBool:
      return Value{!std::get<bool>(v)};
    case Kind::kInt:
      if (auto c = other_number(static_cast<double>(std::get<std::int64_t>(v)))) {
        return Value{static_cast<std::int64_t>(*c)};
      }
      return std::nullopt;
    case Kind::kReal:
      if (auto c = other_number(std::get<double>(v))) return Value{*c};
      return std::nullopt;
    case Kind::kText:
      return Value{std::get<std::string>(v) + "_changed"};
    case Kind::kChoice:
      for (const auto& c : f.choices) {
        if (c != std::get<std::string>(v)) return Value{c};
      }
      return std::nullopt;
    case Kind::kList: {
      auto list = std::get<std::vector<double>>(v);
      if (auto c = other_number(list.at(0))) {
        list[0] = *c;
        return Value{list};
      }
      return std::nullopt;
    }
  }
  return std::nullopt;
}

/// Values just outside the range (none for an unbounded side).
inline std::vector<Value> out_of_range_values(const FieldSpec& f) {
  std::vector<double> bad;
  if (std::isfinite(f.range.hi) && f.range.hi < 9e18) bad.push_back(f.range.hi + 1.0);
  if (std::isfinite(f.range.lo) && f.range.lo > -9e18) {
    bad.push_back(f.range.lo_open ? f.range.lo : f.range.lo - 1.0);
  }
  std::vector<Value> out;
  for (double x : bad) {
    if (f.kind == Kind::kInt) out.emplace_back(static_cast<std::int64_t>(std::floor(x)));
    if (f.kind == Kind::kReal) out.emplace_back(x);
    if (f.kind == Kind::kList && f.list_size != 0) {
      out.emplace_back(std::vector<double>(f.list_size, std::floor(x)));
    }
    if (f.kind == Kind::kList && f.list_size == 0) out.emplace_back(std::vector<double>{x});
  }
  return out;
}

/// Every check of the header comment on table; shipped = the component's config/*.yaml.
template <typename S>
void expect_table_contract(const FieldTable<S>& table, const std::string& shipped) {
  const S defaults;
  // Struct defaults come from the table.
  for (const auto& f : table.fields) {
    EXPECT_EQ(value_text(f.get(defaults)), value_text(f.fallback)) << "default of " << f.key;
    EXPECT_TRUE(check_value(f, f.fallback)) << "default of " << f.key << " outside its range";
  }
  EXPECT_TRUE(check_fields(table, defaults)) << check_fields(table, defaults).error();

  // The shipped file loads to the defaults.
  auto loaded = load_fields(table, shipped);
  ASSERT_TRUE(loaded.ok()) << loaded.error();
  for (const auto& f : table.fields) {
    EXPECT_EQ(value_text(f.get(*loaded)), value_text(f.get(defaults)))
        << shipped << ": " << f.key << " differs from the default";
  }

  // Every key round-trips: change it alone, write YAML, read it back.
  const Values base = values(table, defaults);
  int varied = 0;
  for (std::size_t i = 0; i < base.size(); ++i) {
    const auto& f = table.fields[i];
    auto other = other_value(f, base[i].second);
    if (!other) continue;
    S expected = defaults;
    f.set(expected, *other);
    if (table.cross_check && !table.cross_check(expected)) continue;  // a rule between fields
    Values changed = base;
    changed[i].second = *other;
    auto back = parse_fields(table, yaml_text(changed), "changed.yaml");
    ASSERT_TRUE(back.ok()) << f.key << " = " << value_text(*other) << ": " << back.error();
    ++varied;
    EXPECT_EQ(yaml_text(values(table, *back)), yaml_text(changed)) << f.key;
  }
  EXPECT_GE(varied * 4, static_cast<int>(base.size()) * 3) << "too few keys could be varied";

  // Out of range: refused, naming file and key.
  for (std::size_t i = 0; i < base.size(); ++i) {
    const auto& f = table.fields[i];
    for (const auto& bad : out_of_range_values(f)) {
      Values changed = base;
      changed[i].second = bad;
      auto back = parse_fields(table, yaml_text(changed), "bad.yaml");
      ASSERT_FALSE(back.ok()) << f.key << " = " << value_text(bad) << " was accepted";
      EXPECT_TRUE(contains(back.error(), "bad.yaml: key '" + f.key + "'")) << back.error();
    }
  }

  // Missing required keys and unknown keys: refused, naming file and key.
  for (std::size_t i = 0; i < base.size(); ++i) {
    if (table.fields[i].optional) continue;
    Values without = base;
    without.erase(without.begin() + static_cast<std::ptrdiff_t>(i));
    auto back = parse_fields(table, yaml_text(without), "short.yaml");
    ASSERT_FALSE(back.ok()) << base[i].first << " missing was accepted";
    EXPECT_TRUE(contains(back.error(), "short.yaml: key '" + base[i].first + "': missing"))
        << back.error();
  }
  const std::string first_key = base.front().first;
  const std::string section = first_key.substr(0, first_key.rfind('.') + 1);
  for (const std::string& unknown : {std::string("no_such_key"), section + "no_such_key"}) {
    Values extra = base;
    extra.emplace_back(unknown, Value{1.0});
    auto back = parse_fields(table, yaml_text(extra), "typo.yaml");
    ASSERT_FALSE(back.ok()) << unknown << " was accepted";
    EXPECT_EQ(back.error(), "typo.yaml: key '" + unknown + "': unknown parameter");
  }

  // A duplicated key: refused, naming both lines.
  const std::string text = yaml_text(base);
  const std::string first_line = text.substr(0, text.find('\n') + 1);
  if (first_line.find(':') != std::string::npos && first_line[0] != ' ') {
    auto back = parse_fields(table, text + first_line, "twice.yaml");
    ASSERT_FALSE(back.ok());
    EXPECT_TRUE(contains(back.error(), "appears twice")) << back.error();
  }
}

/// The README at readme holds the table's markdown between the lines
/// "<!-- params:begin -->" and "<!-- params:end -->" (regenerate with `NODE --help-params`).
template <typename S>
void expect_readme_table(const FieldTable<S>& table, const std::string& readme) {
  const std::string text = read_text(readme);
  const std::string begin = "<!-- params:begin -->\n";
  const auto from = text.find(begin);
  const auto to = text.find("<!-- params:end -->");
  ASSERT_NE(from, std::string::npos) << readme << " has no " << begin;
  ASSERT_NE(to, std::string::npos) << readme << " has no params:end marker";
  EXPECT_EQ(text.substr(from + begin.size(), to - from - begin.size()),
            markdown_table(specs(table)))
      << readme << ": the parameter table differs from the generated one";
}

}  // namespace stereoball::params::testing
