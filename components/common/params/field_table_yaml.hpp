#pragma once
// A FieldTable (field_table.hpp) against YAML: reads a Params struct from a parameters file and
// writes one back. The rule: every key of the table is required unless the table marks it
// optional (then its default applies); keys the table does not list are refused, as are
// duplicated keys (yaml_load.hpp); values outside their range are refused. Every error names
// the file and the key: "config/tracker.yaml: key 'max_range_m': 25 is out of range [0.1, 1000] m".

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/params/field_table.hpp"
#include "common/params/params_file.hpp"
#include "common/util/result.hpp"

namespace stereoball::params {

/// The value of one field as the file holds it (type checked, range not yet); nullopt when the
/// key is missing or of the wrong type (the error is recorded in file, see ParamsFile::finish).
std::optional<Value> read_value(ParamsFile& file, const FieldSpec& spec);

/// YAML text of (dotted key, value) pairs as nested mappings, in the given order.
std::string yaml_text(const std::vector<std::pair<std::string, Value>>& values);

/// Reads every field of table from file, checks ranges and the cross-field rules.
template <typename S>
Result<S> read_fields(const FieldTable<S>& table, ParamsFile& file) {
  S s;
  apply_defaults(table, s);
  for (const auto& f : table.fields) {
    if (f.optional && !file.has(f.key)) continue;
    auto v = read_value(file, f);
    if (!v) continue;
    if (auto st = check_value(f, *v); !st) {
      file.fail(st.error());
      continue;
    }
    f.set(s, *v);
  }
  if (auto st = file.finish(); !st) return Error{st.error()};
  if (table.cross_check) {
    if (auto st = table.cross_check(s); !st) return Error{file.name() + ": " + st.error()};
  }
  return s;
}

/// Loads the parameters file at path (see read_fields).
template <typename S>
Result<S> load_fields(const FieldTable<S>& table, const std::string& path) {
  auto file = ParamsFile::load(path);
  if (!file) return Error{file.error()};
  return read_fields(table, *file);
}

/// Parses YAML text; name stands for the file in error messages.
template <typename S>
Result<S> parse_fields(const FieldTable<S>& table, const std::string& text,
                       const std::string& name) {
  auto file = ParamsFile::parse(text, name);
  if (!file) return Error{file.error()};
  return read_fields(table, *file);
}

/// s as a parameters file that read_fields reads back to the same values.
template <typename S>
std::string to_yaml(const FieldTable<S>& table, const S& s) {
  return yaml_text(values(table, s));
}

}  // namespace stereoball::params
