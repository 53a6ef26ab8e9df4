#pragma once
// Result types of the camera server: the project's Result/Status (common/util/result.hpp),
// a value or success, or a one-line error naming the problem.

#include "common/util/result.hpp"

namespace stereoball::camera_server {

using stereoball::Error;
using stereoball::Result;
using stereoball::Status;

/// Builds a failed result from a message.
inline Error fail(std::string message) {
  return Error{std::move(message)};
}

}  // namespace stereoball::camera_server
