#include "common/params/field_table.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <string>

namespace stereoball::params {
namespace {

// Shortest decimal text that reads back to exactly v (so YAML written here round-trips).
std::string real_text(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  if (std::isnan(v)) return "nan";
  char buf[64];
  // Plain digits where people read them that way (200000.0, 0.0004), exponents beyond.
  const double a = std::fabs(v);
  const bool plain = a == 0.0 || (a >= 1e-5 && a < 1e15);
  const auto end = plain ? std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed).ptr
                         : std::to_chars(buf, buf + sizeof buf, v).ptr;
  std::string s(buf, end);
  // A real that prints as a whole number keeps a ".0" so YAML readers see a real.
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return s;
}

// Range ends as people write them: 20, 0.1, 1e+10 -> whole numbers without ".0".
std::string bound_text(double v) {
  if (std::isfinite(v) && v == std::floor(v) && std::fabs(v) < 1e15) {
    return std::to_string(static_cast<long long>(v));
  }
  return real_text(v);
}

std::string with_unit(const std::string& text, const std::string& unit) {
  return unit.empty() ? text : text + " " + unit;
}

std::string key_error(const FieldSpec& spec, const std::string& what) {
  return "key '" + spec.key + "': " + what;
}

Status check_number(const FieldSpec& spec, double v, const std::string& shown) {
  if (spec.range.contains(v)) return {};
  return Error{
      key_error(spec, shown + " is out of range " + with_unit(spec.range.text(), spec.unit))};
}

Status check_list(const FieldSpec& spec, const std::vector<double>& list) {
  if (spec.list_size != 0 && list.size() != spec.list_size) {
    return Error{key_error(spec, "expected " + std::to_string(spec.list_size) + " numbers, got " +
                                     std::to_string(list.size()))};
  }
  if (list.empty()) return Error{key_error(spec, "expected at least one number")};
  for (double x : list) {
    if (spec.whole_numbers && x != std::floor(x)) {
      return Error{key_error(spec, "entries must be whole numbers, got " + real_text(x))};
    }
    if (!spec.range.contains(x)) {
      return Error{key_error(spec, "entry " + bound_text(x) + " is out of range " +
                                       with_unit(spec.range.text(), spec.unit))};
    }
  }
  return {};
}

}  // namespace

std::string Range::text() const {
  if (std::isinf(lo) && std::isinf(hi)) return "any";
  return (lo_open ? "(" : "[") + bound_text(lo) + ", " + bound_text(hi) + "]";
}

std::string value_text(const Value& v) {
  struct Visitor {
    std::string operator()(bool b) const { return b ? "true" : "false"; }
    std::string operator()(std::int64_t i) const { return std::to_string(i); }
    std::string operator()(double d) const { return real_text(d); }
    std::string operator()(const std::string& s) const { return s; }
    std::string operator()(const std::vector<double>& list) const {
      std::string out = "[";
      for (std::size_t i = 0; i < list.size(); ++i) {
        out += (i ? ", " : "") + bound_text(list[i]);
      }
      return out + "]";
    }
  };
  return std::visit(Visitor{}, v);
}

std::string allowed_text(const FieldSpec& spec) {
  switch (spec.kind) {
    case Kind::kBool:
      return "true/false";
    case Kind::kInt:
    case Kind::kReal:
      return spec.range.text();
    case Kind::kText:
      return "text";
    case Kind::kChoice: {
      std::string out;
      for (const auto& c : spec.choices) out += (out.empty() ? "" : ", ") + c;
      return out;
    }
    case Kind::kList: {
      const std::string count = spec.list_size ? std::to_string(spec.list_size) : "1 or more";
      const std::string what = spec.whole_numbers ? " whole numbers" : " numbers";
      return count + what + " in " + spec.range.text();
    }
  }
  return "";
}

Status check_value(const FieldSpec& spec, const Value& v) {
  switch (spec.kind) {
    case Kind::kBool:
    case Kind::kText:
      return {};
    case Kind::kInt: {
      const auto i = std::get<std::int64_t>(v);
      return check_number(spec, static_cast<double>(i), std::to_string(i));
    }
    case Kind::kReal: {
      const double d = std::get<double>(v);
      return check_number(spec, d, bound_text(d));
    }
    case Kind::kChoice: {
      const auto& word = std::get<std::string>(v);
      for (const auto& c : spec.choices) {
        if (c == word) return {};
      }
      return Error{key_error(spec, "'" + word + "' is not one of: " + allowed_text(spec))};
    }
    case Kind::kList:
      return check_list(spec, std::get<std::vector<double>>(v));
  }
  return {};
}

std::string out_of_range(const std::string& key, double v, const Range& r, const std::string& unit,
                         const std::string& why) {
  return "key '" + key + "': " + bound_text(v) + " is out of range " + with_unit(r.text(), unit) +
         (why.empty() ? "" : " (" + why + ")");
}

// A '|' inside a cell would end it.
static std::string cell(const std::string& text) {
  std::string out;
  for (char c : text) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

std::string markdown_table(const std::vector<FieldSpec>& specs) {
  std::string out = "| key | default | allowed | unit | description |\n|---|---|---|---|---|\n";
  for (const auto& s : specs) {
    const std::string shown =
        s.kind == Kind::kText && value_text(s.fallback).empty() ? "\"\"" : value_text(s.fallback);
    out += "| `" + s.key + "` | " + cell(shown) + " | " + cell(allowed_text(s)) + " | " + s.unit +
           " | " + cell(s.text) + (s.optional ? " (optional)" : "") + " |\n";
  }
  return out;
}

}  // namespace stereoball::params
