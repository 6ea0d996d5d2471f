#include "core/base/span.h"

#include <gtest/gtest.h>

#include <vector>

namespace ale {
namespace {

TEST(Span, ViewsARunWithoutOwningIt) {
  std::vector<int> v{4, 5, 6, 7};
  const Span<int> s(v.data(), 4);
  ASSERT_EQ(s.size(), 4);
  EXPECT_FALSE(s.empty());
  s[1] = 50;  // writes through to the container
  EXPECT_EQ(v[1], 50);
  int sum = 0;
  for (int x : s) sum += x;
  EXPECT_EQ(sum, 4 + 50 + 6 + 7);
  EXPECT_EQ(s.first(2).size(), 2);
  EXPECT_EQ(s.first(9).size(), 4);   // capped at the run
  EXPECT_EQ(s.first(-1).size(), 0);  // a negative count is empty
  const Span<const int> c(v.data(), 4);
  EXPECT_EQ(c.end() - c.begin(), 4);
}

TEST(Span, NullOrNegativeIsEmpty) {
  EXPECT_TRUE(Span<int>().empty());
  EXPECT_TRUE(Span<int>(nullptr, 3).empty());
  int x = 1;
  EXPECT_TRUE(Span<int>(&x, -2).empty());
  EXPECT_EQ(Span<int>(&x, -2).begin(), Span<int>(&x, -2).end());
}

}  // namespace
}  // namespace ale
