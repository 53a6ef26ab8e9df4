#include "common/util/enum_names.hpp"

#include <gtest/gtest.h>

namespace stereoball::util {
namespace {

enum class Colour { kRed, kGreen, kBlue };

constexpr EnumName<Colour> kColourNames[] = {
    {Colour::kRed, "red"},
    {Colour::kGreen, "green"},
};

TEST(EnumNames, NameOfGivesTheTablesName) {
  // Given a table with two of the three colours
  // When a listed value is named
  // Then its row's name is returned
  EXPECT_EQ(name_of(kColourNames, Colour::kRed), "red");
  EXPECT_EQ(name_of(kColourNames, Colour::kGreen), "green");
}

TEST(EnumNames, NameOfAValueNotInTheTableIsTheFallback) {
  // Given a value the table lacks
  // When it is named, with and without a fallback
  // Then the fallback ("unknown" by default) is returned and find_name says none
  EXPECT_EQ(name_of(kColourNames, Colour::kBlue), "unknown");
  EXPECT_EQ(name_of(kColourNames, Colour::kBlue, "?"), "?");
  EXPECT_FALSE(find_name(kColourNames, Colour::kBlue).has_value());
  EXPECT_EQ(find_name(kColourNames, Colour::kGreen).value(), "green");
}

TEST(EnumNames, ValueOfParsesExactNamesOnly) {
  // Given the table
  // When names are parsed
  // Then listed names give their value; other case, padding or unknown names give none
  EXPECT_EQ(value_of(kColourNames, "green"), Colour::kGreen);
  EXPECT_EQ(value_of(kColourNames, "red"), Colour::kRed);
  EXPECT_FALSE(value_of(kColourNames, "Red").has_value());
  EXPECT_FALSE(value_of(kColourNames, "red ").has_value());
  EXPECT_FALSE(value_of(kColourNames, "blue").has_value());
  EXPECT_FALSE(value_of(kColourNames, "").has_value());
}

TEST(EnumNames, WorksAtCompileTimeAndOnPlainIntegers) {
  // Given a table keyed by integers (an IDL enum read as its number)
  constexpr EnumName<int> kNumbers[] = {{1, "one"}, {2, "two"}};
  // When it is used in constant expressions
  // Then names and values come out at compile time, both ways round
  static_assert(name_of(kNumbers, 2) == "two");
  static_assert(value_of(kNumbers, "one").value() == 1);
  static_assert(name_of(kColourNames, Colour::kBlue, "none") == "none");
  EXPECT_EQ(name_of(kNumbers, 3), "unknown");
}

}  // namespace
}  // namespace stereoball::util
