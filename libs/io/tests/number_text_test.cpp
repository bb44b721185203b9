#include "omnisfm/io/number_text.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace omnisfm::io {
namespace {

TEST(NumberText, ParsesWholeFieldsOnly) {
  double value = 0;
  EXPECT_TRUE(parse_double("1.5", &value));
  EXPECT_EQ(value, 1.5);
  EXPECT_TRUE(parse_double("+2e-3", &value));
  EXPECT_EQ(value, 2e-3);
  EXPECT_TRUE(parse_double("-7", &value));
  EXPECT_EQ(value, -7);
  value = 42;
  EXPECT_FALSE(parse_double("1.5x", &value));
  EXPECT_FALSE(parse_double("", &value));
  EXPECT_FALSE(parse_double("abc", &value));
  EXPECT_FALSE(parse_double("+-1", &value));
  EXPECT_FALSE(parse_double(" 1", &value));
  EXPECT_FALSE(parse_double("1e999", &value));
  EXPECT_EQ(value, 42);
}

// A number beyond a double's range is said to be so, not to be no number at all.
TEST(NumberText, SaysWhyAFieldIsNotADouble) {
  EXPECT_EQ(not_a_double_reason("1e400"), "is out of range");
  EXPECT_EQ(not_a_double_reason("-1e400"), "is out of range");
  EXPECT_EQ(not_a_double_reason("+1e400"), "is out of range");
  EXPECT_EQ(not_a_double_reason("1e400x"), "is not a number");
  EXPECT_EQ(not_a_double_reason("abc"), "is not a number");
  EXPECT_EQ(not_a_double_reason(""), "is not a number");
}

TEST(NumberText, ParsesIntegers) {
  int value = 0;
  EXPECT_TRUE(parse_int("1024", &value));
  EXPECT_EQ(value, 1024);
  EXPECT_TRUE(parse_int("-3", &value));
  EXPECT_EQ(value, -3);
  EXPECT_FALSE(parse_int("10.5", &value));
  EXPECT_FALSE(parse_int("1e3", &value));
  EXPECT_FALSE(parse_int("99999999999", &value));
}

TEST(NumberText, FormatsCompactlyAndReadsBackExactly) {
  EXPECT_EQ(format_double(800), "800");
  EXPECT_EQ(format_double(0.1), "0.1");
  EXPECT_EQ(format_double(511.5), "511.5");
  EXPECT_EQ(format_double(-0.25), "-0.25");

  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> mantissa(-1, 1);
  std::uniform_int_distribution<int> exponent(-30, 30);
  for (int i = 0; i < 10000; ++i) {
    const double original = std::ldexp(mantissa(random), exponent(random));
    double parsed = 0;
    ASSERT_TRUE(parse_double(format_double(original), &parsed));
    ASSERT_EQ(parsed, original) << format_double(original);
  }
  const double smallest = std::numeric_limits<double>::denorm_min();
  double parsed = 0;
  ASSERT_TRUE(parse_double(format_double(smallest), &parsed));
  EXPECT_EQ(parsed, smallest);
}

}  // namespace
}  // namespace omnisfm::io
