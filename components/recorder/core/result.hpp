#pragma once
// A value or an error message: how the recorder library reports expected failures.

#include <optional>
#include <string>
#include <utility>

namespace stereoball::recorder {

/// Holds either a T or a one-line error message naming the problem.
template <class T>
class Result {
 public:
  /// A successful result holding value.
  static Result ok(T value) { return Result(std::move(value), {}); }
  /// A failed result; message names the problem.
  static Result fail(std::string message) { return Result(std::nullopt, std::move(message)); }

  /// True when a value is held.
  bool has_value() const { return value_.has_value(); }
  explicit operator bool() const { return has_value(); }
  /// The value; only valid when has_value().
  const T& value() const& { return *value_; }
  T& value() & { return *value_; }
  T&& value() && { return std::move(*value_); }
  const T& operator*() const& { return *value_; }
  T& operator*() & { return *value_; }
  const T* operator->() const { return &*value_; }
  T* operator->() { return &*value_; }
  /// The error message; empty when has_value().
  const std::string& error() const { return error_; }

 private:
  Result(std::optional<T> value, std::string error)
      : value_(std::move(value)), error_(std::move(error)) {}
  std::optional<T> value_;
  std::string error_;
};

/// Outcome of an operation without a value: std::nullopt on success, else the error message.
using Status = std::optional<std::string>;

}  // namespace stereoball::recorder
