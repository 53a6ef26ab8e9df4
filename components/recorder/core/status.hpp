#pragma once
// Outcome of a recorder operation that has no value (operations with a value return
// stereoball::Result<T> from common/util/result.hpp).

#include <optional>
#include <string>

namespace stereoball::recorder {

/// Outcome of an operation without a value: std::nullopt on success, else the error message.
using Status = std::optional<std::string>;

}  // namespace stereoball::recorder
