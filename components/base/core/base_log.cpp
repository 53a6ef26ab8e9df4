#include "base/core/base_log.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>
#include <type_traits>
#include <vector>

#include "common/util/enum_names.hpp"

namespace stereoball::base {
namespace {

constexpr util::EnumName<BaseEventKind> kKindNames[] = {
    {BaseEventKind::kCommand, "cmd"},
    {BaseEventKind::kEstop, "estop"},
    {BaseEventKind::kFrame, "frame"},
};

std::string clean(std::string_view text) {
  // One token: spaces and '=' would break the line's fields.
  std::string out;
  for (char c : text.substr(0, 64)) {
    const bool printable = c > ' ' && c < 127 && c != '=';
    out += printable ? c : '_';
  }
  return out.empty() ? "-" : out;
}

template <typename T>
Result<T> number(const std::map<std::string, std::string, std::less<>>& fields,
                 std::string_view key) {
  const auto it = fields.find(key);
  if (it == fields.end()) return Error{"base log line: missing field '" + std::string(key) + "'"};
  const std::string& text = it->second;
  if constexpr (std::is_floating_point_v<T>) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (end == text.c_str() || *end != '\0' || !std::isfinite(v))
      return Error{"base log line: field '" + std::string(key) + "' is not a number: " + text};
    return static_cast<T>(v);
  } else {
    T v{};
    const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (ec != std::errc{} || ptr != text.data() + text.size())
      return Error{"base log line: field '" + std::string(key) + "' is not an integer: " + text};
    return v;
  }
}

}  // namespace

std::string format_base_event(const BaseEvent& e) {
  char buf[256];
  std::string line(util::name_of(kKindNames, e.kind));
  std::snprintf(buf, sizeof buf, " t=%lld estop=%d lin=%.6g ang=%.6g",
                static_cast<long long>(e.time_ns), e.estop_engaged ? 1 : 0, e.linear_mps,
                e.angular_radps);
  line += buf;
  if (e.kind == BaseEventKind::kFrame) return line;
  line += " state=" + std::string(to_string(e.state));
  if (e.kind == BaseEventKind::kEstop) return line;
  std::snprintf(buf, sizeof buf, " stamp=%lld seq=%llu key=%u auth=%d",
                static_cast<long long>(e.stamp_ns), static_cast<unsigned long long>(e.seq),
                e.key_id, e.authenticated ? 1 : 0);
  line += buf;
  line += " source=" + clean(e.source);
  return line;
}

Result<BaseEvent> parse_base_event(std::string_view line) {
  std::vector<std::string_view> tokens;
  while (!line.empty()) {
    const size_t space = line.find(' ');
    const std::string_view token = line.substr(0, space);
    if (!token.empty()) tokens.push_back(token);
    if (space == std::string_view::npos) break;
    line.remove_prefix(space + 1);
  }
  if (tokens.empty()) return Error{"base log line: empty"};
  BaseEvent e;
  const auto kind = util::value_of(kKindNames, tokens[0]);
  if (!kind) return Error{"base log line: unknown event '" + std::string(tokens[0]) + "'"};
  e.kind = *kind;
  std::map<std::string, std::string, std::less<>> fields;
  for (size_t i = 1; i < tokens.size(); ++i) {
    const size_t eq = tokens[i].find('=');
    if (eq == std::string_view::npos)
      return Error{"base log line: field without '=': " + std::string(tokens[i])};
    fields[std::string(tokens[i].substr(0, eq))] = std::string(tokens[i].substr(eq + 1));
  }
  auto t = number<int64_t>(fields, "t");
  auto estop = number<int>(fields, "estop");
  auto lin = number<double>(fields, "lin");
  auto ang = number<double>(fields, "ang");
  if (!t) return Error{t.error()};
  if (!estop) return Error{estop.error()};
  if (!lin) return Error{lin.error()};
  if (!ang) return Error{ang.error()};
  e.time_ns = *t;
  e.estop_engaged = *estop != 0;
  e.linear_mps = *lin;
  e.angular_radps = *ang;
  if (e.kind == BaseEventKind::kFrame) return e;
  const auto state = fields.find("state");
  if (state == fields.end()) return Error{"base log line: missing field 'state'"};
  const auto parsed_state = gate_state_from_string(state->second);
  if (!parsed_state) return Error{"base log line: unknown gate state '" + state->second + "'"};
  e.state = *parsed_state;
  if (e.kind == BaseEventKind::kEstop) return e;
  auto stamp = number<int64_t>(fields, "stamp");
  auto seq = number<uint64_t>(fields, "seq");
  auto key = number<uint32_t>(fields, "key");
  auto authenticated = number<int>(fields, "auth");
  if (!stamp) return Error{stamp.error()};
  if (!seq) return Error{seq.error()};
  if (!key) return Error{key.error()};
  if (!authenticated) return Error{authenticated.error()};
  e.stamp_ns = *stamp;
  e.seq = *seq;
  e.key_id = *key;
  e.authenticated = *authenticated != 0;
  const auto source = fields.find("source");
  e.source = source == fields.end() ? "-" : source->second;
  return e;
}

}  // namespace stereoball::base
