#include "core/map/event_log.h"

#include <gtest/gtest.h>

#include <vector>

namespace ale::map {
namespace {

std::vector<int> read_all(const EventLog<int>& log, EventCursor& c, std::uint64_t* lost = nullptr) {
  std::vector<int> out;
  const std::uint64_t n = log.read(c, [&](int e) { out.push_back(e); });
  if (lost) *lost = n;
  return out;
}

TEST(EventLog, EachCursorReadsEveryEventOnceAtItsOwnPace) {
  EventLog<int> log(4);
  EventCursor a, b;
  log.push(1);
  log.push(2);
  EXPECT_EQ(read_all(log, a), (std::vector<int>{1, 2}));
  log.push(3);
  EXPECT_EQ(read_all(log, a), (std::vector<int>{3}));
  EXPECT_EQ(read_all(log, b), (std::vector<int>{1, 2, 3}));
  EXPECT_TRUE(read_all(log, a).empty());
  EventCursor late = log.cursor();  // joins now: only what comes next
  log.push(4);
  EXPECT_EQ(log.pending(b), 1u);
  EXPECT_EQ(read_all(log, late), (std::vector<int>{4}));
  EXPECT_EQ(a.lost + b.lost + late.lost, 0u);
}

TEST(EventLog, ACursorThatFellBehindIsToldWhatItLost) {
  EventLog<int> log(3);
  EventCursor slow, fast;
  for (int i = 1; i <= 5; ++i) {
    log.push(i);
    (void)read_all(log, fast);
  }
  std::uint64_t lost = 0;
  EXPECT_EQ(read_all(log, slow, &lost), (std::vector<int>{3, 4, 5}));  // 1 and 2 were overwritten
  EXPECT_EQ(lost, 2u);
  EXPECT_EQ(slow.lost, 2u);
  EXPECT_EQ(fast.lost, 0u);
  for (int i = 6; i <= 13; ++i) log.push(i);
  EXPECT_EQ(read_all(log, slow, &lost), (std::vector<int>{11, 12, 13}));
  EXPECT_EQ(lost, 5u);
  EXPECT_EQ(slow.lost, 7u);
  EXPECT_EQ(log.head(), 13u);
}

TEST(EventLog, ACursorFromAnotherLogReadsNothing) {
  EventLog<int> a(4), b(4);
  for (int i = 0; i < 3; ++i) a.push(i);
  EventCursor c = a.cursor();
  b.push(7);
  std::uint64_t lost = 1;
  EXPECT_TRUE(read_all(b, c, &lost).empty());
  EXPECT_EQ(lost, 0u);
  b.push(8);
  EXPECT_EQ(read_all(b, c), (std::vector<int>{8}));
}

}  // namespace
}  // namespace ale::map
