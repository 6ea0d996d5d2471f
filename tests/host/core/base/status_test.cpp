#include "core/base/status.h"

#include <gtest/gtest.h>

#include <string>

namespace ale {
namespace {

TEST(StatusTest, DefaultIsOk) {
  Status s;
  EXPECT_TRUE(s.ok());
  EXPECT_EQ(s.to_string(), "ok");
}

TEST(StatusTest, ErrorCarriesCodeAndReason) {
  Status s = corrupt_data("data.csv:7: expected 2 columns, found 3");
  EXPECT_FALSE(s.ok());
  EXPECT_EQ(s.code(), StatusCode::kCorruptData);
  EXPECT_EQ(s.to_string(), "corrupt data: data.csv:7: expected 2 columns, found 3");
}

Status fails_then_never_reaches(int* reached) {
  ALE_RETURN_IF_ERROR(not_found("x"));
  *reached = 1;
  return {};
}

TEST(StatusTest, ReturnIfErrorStopsAtFirstFailure) {
  int reached = 0;
  Status s = fails_then_never_reaches(&reached);
  EXPECT_EQ(s.code(), StatusCode::kNotFound);
  EXPECT_EQ(reached, 0);
}

TEST(ResultTest, HoldsValueOrStatus) {
  Result<std::string> good(std::string("frame"));
  ASSERT_TRUE(good.ok());
  EXPECT_EQ(*good, "frame");
  Result<int> bad(io_error("read failed"));
  EXPECT_FALSE(bad.ok());
  EXPECT_EQ(bad.status().code(), StatusCode::kIoError);
}

TEST(ResultTest, OkStatusWithoutValueIsAnInternalError) {
  Result<int> r{Status()};
  EXPECT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kInternal);
}

}  // namespace
}  // namespace ale
