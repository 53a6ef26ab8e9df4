#pragma once
// How expected failures travel (no exceptions): Result<T> carries a value or an Error, Status
// carries success or an Error. Both are truthy on success and give the message with error().

#include <optional>
#include <string>
#include <utility>
#include <variant>

namespace stereoball {

/// Error text, always naming what was wrong (file, key, field, device...).
struct Error {
  std::string message;
};

/// Either a T or an Error.
template <typename T>
class Result {
 public:
  Result(T value) : v_(std::move(value)) {}      // NOLINT(google-explicit-constructor)
  Result(Error error) : v_(std::move(error)) {}  // NOLINT(google-explicit-constructor)

  bool ok() const { return std::holds_alternative<T>(v_); }
  explicit operator bool() const { return ok(); }
  T& value() & { return std::get<T>(v_); }
  const T& value() const& { return std::get<T>(v_); }
  T&& value() && { return std::get<T>(std::move(v_)); }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  const std::string& error() const { return std::get<Error>(v_).message; }

 private:
  std::variant<T, Error> v_;
};

/// Success or an Error, for operations that return no value: `return {};` succeeds,
/// `return Error{"what was wrong"};` fails.
class Status {
 public:
  Status() = default;
  Status(Error error) : error_(std::move(error.message)) {}  // NOLINT(google-explicit-constructor)

  bool ok() const { return !error_.has_value(); }
  explicit operator bool() const { return ok(); }
  /// Throws std::bad_optional_access on success (like Result::error, a bug, never UB).
  const std::string& error() const { return error_.value(); }

 private:
  std::optional<std::string> error_;
};

}  // namespace stereoball
