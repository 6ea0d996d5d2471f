#include "tests/host/core/optim/alloc_counter.h"

#include <cstddef>
#include <cstdlib>
#include <new>

namespace {
thread_local long g_allocations = 0;
thread_local bool g_counting = false;
void note() {
  if (g_counting) ++g_allocations;
}
}  // namespace

namespace ale::test {
long allocation_count() { return g_allocations; }
void set_counting(bool on) { g_counting = on; }
}  // namespace ale::test

extern "C" {
void* __real_malloc(std::size_t n);
void* __real_calloc(std::size_t n, std::size_t size);
void* __real_realloc(void* p, std::size_t n);
void* __real_aligned_alloc(std::size_t align, std::size_t n);
int __real_posix_memalign(void** p, std::size_t align, std::size_t n);

void* __wrap_malloc(std::size_t n) {
  note();
  return __real_malloc(n);
}
void* __wrap_calloc(std::size_t n, std::size_t size) {
  note();
  return __real_calloc(n, size);
}
void* __wrap_realloc(void* p, std::size_t n) {
  note();
  return __real_realloc(p, n);
}
void* __wrap_aligned_alloc(std::size_t align, std::size_t n) {
  note();
  return __real_aligned_alloc(align, n);
}
int __wrap_posix_memalign(void** p, std::size_t align, std::size_t n) {
  note();
  return __real_posix_memalign(p, align, n);
}
}

// libstdc++'s operator new calls malloc inside the (unwrapped) library: replace it here.
void* operator new(std::size_t n) {
  void* p = __wrap_malloc(n == 0 ? 1 : n);
  if (p == nullptr) throw std::bad_alloc();
  return p;
}
void* operator new[](std::size_t n) { return operator new(n); }
void* operator new(std::size_t n, std::align_val_t a) {
  const std::size_t align = static_cast<std::size_t>(a);
  void* p = __wrap_aligned_alloc(align, (n + align - 1) / align * align);
  if (p == nullptr) throw std::bad_alloc();
  return p;
}
void* operator new[](std::size_t n, std::align_val_t a) { return operator new(n, a); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
