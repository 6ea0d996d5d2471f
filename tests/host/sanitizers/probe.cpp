// A program with one deliberate error per sanitizer, chosen by its argument: it proves, in the
// sanitizer build, that each kind of finding ends the process with the sanitizers' exit status 23
// and its report (CMakeLists.txt beside this file; cmake/sanitizer_defaults.cpp sets the status).
// Built and run only in the sanitizer build: anywhere else these are plain bugs.
//
//   sanitizer_probe heap-overflow|use-after-free|leak|signed-overflow|none
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace {

// Sizes and operands are read through volatile so that the compiler cannot see the error (nor
// fold it away, nor let UBSan's object-size check catch it first): what runs is each sanitizer's
// own check at run time.
std::size_t opaque(std::size_t v) {
  volatile std::size_t x = v;
  return x;
}

int heap_overflow(std::size_t n) {
  char* p = static_cast<char*>(std::malloc(n));
  std::memset(p, 0, n);
  p[n] = 1;  // one byte past the block
  const int v = p[0];
  std::free(p);
  return v;
}

int use_after_free(std::size_t n) {
  char* p = static_cast<char*>(std::malloc(n));
  std::memset(p, 7, n);
  char* volatile kept = p;  // the compiler's own use-after-free warning must not see it either
  std::free(p);
  return kept[n / 2];  // read of freed memory
}

int leak(std::size_t n) {
  char* p = static_cast<char*>(std::malloc(n));
  std::memset(p, 1, n);
  std::printf("allocated %zu bytes at %p and dropped the pointer\n", n, static_cast<void*>(p));
  p = nullptr;
  return 0;
}

int signed_overflow(std::size_t v) {
  const int big = static_cast<int>(v);
  const int sum = big + big;  // 2e9 doubled overflows int: undefined
  std::printf("%d\n", sum);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: sanitizer_probe heap-overflow|use-after-free|leak|signed-overflow|none\n");
    return 2;
  }
  const char* mode = argv[1];
  if (std::strcmp(mode, "heap-overflow") == 0) return heap_overflow(opaque(24));
  if (std::strcmp(mode, "use-after-free") == 0) return use_after_free(opaque(24));
  if (std::strcmp(mode, "leak") == 0) return leak(opaque(4096));
  if (std::strcmp(mode, "signed-overflow") == 0) return signed_overflow(opaque(2000000000));
  if (std::strcmp(mode, "none") == 0) return 0;
  std::fprintf(stderr, "sanitizer_probe: unknown mode '%s'\n", mode);
  return 2;
}
