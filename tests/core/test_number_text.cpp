// The one reading of numbers written as text, against a table of what people type.
#include <gtest/gtest.h>

#include <limits>
#include <new>
#include <optional>
#include <stdexcept>
#include <string>

#include "starnav/core/input_file.hpp"
#include "starnav/core/number_text.hpp"

namespace starnav {
namespace {

TEST(NumberText, RealsAreDecimalAndFinite) {
  struct Row {
    const char* text;
    std::optional<double> value;
  };
  const Row rows[] = {
      {"2", 2.0},       {"-0.5", -0.5},     {"+1.25", 1.25},   {"1e-3", 1e-3},   {"1E3", 1000.0}, {".5", 0.5},
      {"0x10", {}},     {"0x1p-3", {}},     {"inf", {}},       {"-inf", {}},     {"nan", {}},     {"1e400", {}},
      {"", {}},         {" 1", {}},         {"1 ", {}},        {"1,5", {}},      {"+-1", {}},     {"++1", {}},
      {"+", {}},        {"-", {}},          {"1.2.3", {}},     {"\xEF\xBB\xBF" "1", {}},
  };
  for (const Row& r : rows) {
    SCOPED_TRACE(r.text);
    EXPECT_EQ(parse_real_text(r.text), r.value);
  }
}

TEST(NumberText, IntegersAndCountsNeverWrapOrChangeBase) {
  EXPECT_EQ(parse_integer_text("-7"), -7);
  EXPECT_EQ(parse_integer_text("+7"), 7);
  EXPECT_EQ(parse_integer_text("010"), 10);  // decimal, not octal eight
  EXPECT_EQ(parse_integer_text("0x10"), std::nullopt);
  EXPECT_EQ(parse_integer_text("1.0"), std::nullopt);
  EXPECT_EQ(parse_integer_text("9223372036854775808"), std::nullopt);
  EXPECT_EQ(parse_unsigned_text("18446744073709551615"), std::numeric_limits<std::uint64_t>::max());
  EXPECT_EQ(parse_unsigned_text("18446744073709551616"), std::nullopt);
  EXPECT_EQ(parse_unsigned_text("-1"), std::nullopt);  // not 2^64 - 1
  EXPECT_EQ(parse_unsigned_text("-0"), std::nullopt);
  EXPECT_EQ(parse_unsigned_text("+3"), std::nullopt);  // a count takes no sign, '+' neither
  EXPECT_EQ(parse_unsigned_text(""), std::nullopt);
  EXPECT_EQ(parse_unsigned_text("1e3"), std::nullopt);
}

TEST(NumberText, AWholeNumberInARangeFromZeroIsACountWithoutASign) {
  struct Row {
    const char* text;
    std::int64_t lo, hi;
    std::optional<std::int64_t> expected;
  };
  for (const Row& r : {Row{"7", 0, 10, 7}, Row{"+7", 0, 10, std::nullopt}, Row{"-0", 0, 10, std::nullopt},
                       Row{"11", 0, 10, std::nullopt}, Row{"+7", -5, 10, 7}, Row{"-5", -5, 10, -5}, Row{"-6", -5, 10, std::nullopt},
                       Row{"010", 1, 10, 10}, Row{"18446744073709551615", 0, 10, std::nullopt}})
    EXPECT_EQ(parse_integer_in(r.text, r.lo, r.hi), r.expected) << r.text << " in " << r.lo << ".." << r.hi;
}

TEST(InputFileScope, TheInnermostFileAnExceptionLeavesIsNamedAfterUnwinding) {
  const std::string outer = "outer.yaml", inner = "inner.pgm";
  EXPECT_EQ(input_file_being_read(), nullptr);
  try {
    const InputFileScope a(outer);
    {
      const InputFileScope b(inner);
      EXPECT_EQ(*input_file_being_read(), inner);
    }
    EXPECT_EQ(*input_file_being_read(), outer);
    const InputFileScope c(inner);
    throw std::bad_alloc();
  } catch (const std::bad_alloc&) {
    EXPECT_EQ(input_file_being_read(), nullptr);
    EXPECT_EQ(std::string(input_file_left_by_exception()), inner);
  }
  // A read that ends well leaves no name behind for a later failure elsewhere.
  {
    const InputFileScope ok(outer);
  }
  EXPECT_EQ(std::string(input_file_left_by_exception()), "");
}

}  // namespace
}  // namespace starnav
