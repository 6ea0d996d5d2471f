// Counts heap allocations made by the calling thread while an AllocationCounter is alive: the
// test binary is linked with -Wl,--wrap for malloc, calloc, realloc, aligned_alloc and
// posix_memalign (Eigen allocates with malloc directly) and alloc_counter.cpp replaces the
// global operator new on top of them.
#pragma once

namespace ale::test {

long allocation_count();
void set_counting(bool on);

class AllocationCounter {
 public:
  AllocationCounter() : start_(allocation_count()) { set_counting(true); }
  ~AllocationCounter() { set_counting(false); }
  long count() const { return allocation_count() - start_; }

 private:
  long start_;
};

}  // namespace ale::test
