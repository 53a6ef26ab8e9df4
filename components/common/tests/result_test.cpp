// Result and Status: truthy on success, the message from error(), and error() on a success a
// clean failure (an exception a test reports) rather than a read of nothing.

#include "common/util/result.hpp"

#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <variant>

namespace stereoball {
namespace {

Status check_positive(int v) {
  if (v <= 0) return Error{"value must be > 0, got " + std::to_string(v)};
  return {};
}

Result<int> twice_positive(int v) {
  if (auto st = check_positive(v); !st) return Error{st.error()};
  return 2 * v;
}

TEST(Status, GivenSuccessOrFailureThenTruthinessAndMessageFollow) {
  EXPECT_TRUE(check_positive(3).ok());
  EXPECT_TRUE(static_cast<bool>(check_positive(3)));
  const Status bad = check_positive(-1);
  EXPECT_FALSE(bad.ok());
  EXPECT_EQ(bad.error(), "value must be > 0, got -1");
}

TEST(Status, GivenSuccessWhenTheErrorIsAskedThenItThrowsInsteadOfReadingNothing) {
  EXPECT_THROW((void)check_positive(1).error(), std::bad_optional_access);
}

TEST(Result, GivenSuccessOrFailureThenValueOrMessage) {
  const auto good = twice_positive(4);
  ASSERT_TRUE(good.ok());
  EXPECT_EQ(*good, 8);
  const auto bad = twice_positive(0);
  EXPECT_FALSE(bad.ok());
  EXPECT_EQ(bad.error(), "value must be > 0, got 0");
  EXPECT_THROW((void)good.error(), std::bad_variant_access);
}

}  // namespace
}  // namespace stereoball
