// A fuzz target with deliberate errors, chosen by the input's first bytes: it proves that the fuzz
// build's net holds (tests/fuzz/CMakeLists.txt, the fuzz.net.* tests): a heap overflow, a signed
// overflow (UBSan, fatal) and a leak each stop the run, keep the input and fail run_fuzzer.cmake.
// Its seeds are those inputs, so each run finds its error on the first input. Not a parser.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

namespace {

// Read through volatile, so that neither the compiler nor UBSan's object-size check sees the error
// before the sanitizer's own check at run time does.
std::size_t opaque(std::size_t v) {
  volatile std::size_t x = v;
  return x;
}

bool starts_with(const std::uint8_t* data, std::size_t size, const char* word) {
  const std::size_t n = std::strlen(word);
  return size >= n && std::memcmp(data, word, n) == 0;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (starts_with(data, size, "heap-overflow")) {
    const std::size_t n = opaque(16);
    char* p = static_cast<char*>(std::malloc(n));
    std::memset(p, 0, n);
    volatile char past = p[n];  // one byte past the block
    (void)past;
    std::free(p);
  } else if (starts_with(data, size, "signed-overflow")) {
    volatile int big = 0x7fffffff;
    volatile int sum = big + static_cast<int>(opaque(1));
    (void)sum;
  } else if (starts_with(data, size, "leak")) {
    char* p = static_cast<char*>(std::malloc(opaque(4096)));
    std::memset(p, 1, 4096);
    char* volatile kept = p;
    (void)kept;
  }
  return 0;
}
