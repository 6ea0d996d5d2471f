// A fixed-capacity log of events that several consumers read, each at its own pace: every event
// gets the next sequence number, and a consumer keeps an EventCursor (the sequence number it
// reads next). The log keeps the last `capacity` events; older ones are overwritten, and a
// consumer that fell that far behind is told how many it lost instead of reading stale ones.
// Memory is reserved at construction; pushing and reading never allocate.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ale::map {

struct EventCursor {
  std::uint64_t next = 0;  // sequence number of the next event to read
  std::uint64_t lost = 0;  // events overwritten before this cursor read them, in total
};

template <class E>
class EventLog {
 public:
  explicit EventLog(std::size_t capacity) : ring_(capacity > 0 ? capacity : 1) {}

  void push(const E& e) {
    ring_[static_cast<std::size_t>(head_ % ring_.size())] = e;
    ++head_;
  }

  // A cursor that reads only events pushed from now on.
  EventCursor cursor() const { return EventCursor{head_, 0}; }
  std::uint64_t head() const { return head_; }  // sequence number of the next event pushed
  std::size_t capacity() const { return ring_.size(); }
  // Events that are still kept and that `c` has not read.
  std::uint64_t pending(const EventCursor& c) const { return head_ - oldest(c); }

  // Calls f(event) for every event `c` has not read, oldest first, and moves `c` past them.
  // Returns how many events were overwritten before `c` read them (also added to c.lost); they
  // are skipped.
  template <class F>
  std::uint64_t read(EventCursor& c, F&& f) const {
    const std::uint64_t from = oldest(c);
    const std::uint64_t lost = from > c.next ? from - c.next : 0;
    c.lost += lost;
    for (std::uint64_t s = from; s < head_; ++s) f(ring_[static_cast<std::size_t>(s % ring_.size())]);
    c.next = head_;
    return lost;
  }

 private:
  // the first sequence number `c` can still read
  std::uint64_t oldest(const EventCursor& c) const {
    const std::uint64_t kept_from = head_ > ring_.size() ? head_ - ring_.size() : 0;
    // a cursor ahead of the log (from another log, or before a clear) reads nothing
    if (c.next > head_) return head_;
    return c.next > kept_from ? c.next : kept_from;
  }

  std::vector<E> ring_;
  std::uint64_t head_ = 0;
};

}  // namespace ale::map
