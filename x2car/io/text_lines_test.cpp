#include "x2car/io/text_lines.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string_view>
#include <vector>

#include "x2car/core/error.hpp"
#include "x2car/core/test_matchers.hpp"

namespace x2car::io {
namespace {

using ::testing::HasSubstr;
using x2car::testing::expect_input_error;

TEST(TextLines, SplitsLinesAndFields) {
  const std::vector<TextLine> lines = split_lines("\xEF\xBB\xBF# c\r\n1, ,3\r\n\n 4\t5  6 \n");
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0].number, 2u);
  EXPECT_EQ(lines[1].number, 4u);
  EXPECT_EQ(split_fields(lines[0].text), (std::vector<std::string_view>{"1", "", "3"}));
  EXPECT_EQ(split_fields(lines[1].text), (std::vector<std::string_view>{"4", "5", "6"}));
  EXPECT_EQ(split_lines("a\n\n#b\n", {false, false}).size(), 3u);
}

TEST(TextLines, ParsesNumbersStrictly) {
  const FieldLocation where{"f.csv", 7, field_index(2)};
  EXPECT_EQ(parse_double("+1.5e3", where), 1500.0);
  EXPECT_TRUE(std::isnan(parse_double("nan", where, NonFinite::kAllow)));
  EXPECT_EQ(parse_integer("-42", where), -42);
  for (const char* bad : {"", "1.5x", "1e999", "inf", "0x10", "--1"}) {
    const InputError error = expect_input_error([&] { parse_double(bad, where); }, "f.csv", 7, "3");
    EXPECT_THAT(error.what(), HasSubstr("f.csv:7 (field 3)")) << bad;
  }
  for (const char* bad : {"1.0", "99999999999999999999", "x"}) {
    expect_input_error([&] { parse_integer(bad, where); }, "f.csv", 7, "3");
  }
}

TEST(TextLines, FormatsNumbersForExactRoundTrip) {
  EXPECT_EQ(format_number(0.1), "0.1");
  EXPECT_EQ(format_number(-0.0), "0");
  const double third = 1.0 / 3.0;
  EXPECT_EQ(parse_double(format_number(third), {}), third);
  EXPECT_EQ(format_numbers({1.0, 2.5}, ","), "1,2.5");
}

}  // namespace
}  // namespace x2car::io
