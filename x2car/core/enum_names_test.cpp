#include "x2car/core/enum_names.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <stdexcept>
#include <string>
#include <vector>

namespace x2car {
namespace {

enum class Colour { kRed, kGreen, kBlue };
constexpr std::array<EnumName<Colour>, 2> kColourNames{{
    {Colour::kRed, "red"},
    {Colour::kGreen, "green"},
}};

TEST(EnumNames, OneTableDrivesPrintingParsingAndTheList) {
  EXPECT_STREQ(enum_to_string(kColourNames, Colour::kGreen), "green");
  EXPECT_EQ(enum_from_string(kColourNames, "red", "colour"), Colour::kRed);
  EXPECT_EQ(enum_names(kColourNames), (std::vector<std::string>{"red", "green"}));
  for (const auto& entry : kColourNames) {
    EXPECT_EQ(enum_from_string(kColourNames, enum_to_string(kColourNames, entry.value), "colour"),
              entry.value);
  }
}

TEST(EnumNames, AnUnknownNameListsTheValidOnes) {
  EXPECT_THAT([] { enum_from_string(kColourNames, "Red", "colour"); },
              ::testing::ThrowsMessage<std::invalid_argument>(
                  "unknown colour 'Red'; the valid names are: red, green"));
  EXPECT_THROW(enum_to_string(kColourNames, Colour::kBlue), std::logic_error);
}

}  // namespace
}  // namespace x2car
