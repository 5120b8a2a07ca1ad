#include "rl/core/csv_line.h"

#include <gtest/gtest.h>

namespace rlt {
namespace {

using Fields = std::vector<std::string>;

TEST(CsvLine, EmptyFieldsKeepTheirPlaces) {
  EXPECT_EQ(split_csv_line("a,,b"), (Fields{"a", "", "b"}));
  EXPECT_EQ(split_csv_line("a,,b,"), (Fields{"a", "", "b", ""}));
  EXPECT_EQ(split_csv_line(",a"), (Fields{"", "a"}));
}

TEST(CsvLine, AnEmptyLineHasNoFieldsAndOneWithoutCommasOne) {
  EXPECT_TRUE(split_csv_line("").empty());
  EXPECT_EQ(split_csv_line("step"), (Fields{"step"}));
  EXPECT_EQ(split_csv_line(","), (Fields{"", ""}));
}

}  // namespace
}  // namespace rlt
