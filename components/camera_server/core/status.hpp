#pragma once
// Result types of the camera server: a value or a one-line error naming the problem.

#include "common/util/result.hpp"

namespace stereoball::camera_server {

using stereoball::Error;
using stereoball::Result;

/// Empty success value for operations that return nothing.
struct Ok {};

/// Success or a one-line error.
using Status = Result<Ok>;

/// Builds a failed result from a message.
inline Error fail(std::string message) {
  return Error{std::move(message)};
}

}  // namespace stereoball::camera_server
