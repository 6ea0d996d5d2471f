// Locating ../shared/data for real-data tests: skip with a message when it is missing, fail
// when CI=true (CI must run them).
#pragma once

#include <gtest/gtest.h>

#include <string>

namespace ale::test {

// The data folder: $ALE_DATA_DIR, else the build's default (../shared/data beside the repo).
std::string data_root();
// data_root() + "/" + relative.
std::string data_path(const std::string& relative);
bool running_in_ci();
// True when ALE_TEST_REDUCED=1 (the sanitizer build's ctest sets it for every GoogleTest case,
// cmake/AleTargets.cmake): a test that is slow under the sanitizers then runs a smaller form of
// the same work (fewer frames, one room) through the same code, keeps its checks, and prints
// that it did. ALE_TEST_REDUCED=0 runs the full form anywhere.
bool reduced_run();
// A fresh empty folder under the system's temp dir for a test's fixtures; removed with everything
// in it when the test binary exits (set ALE_KEEP_TEST_DIRS=1 to keep it).
std::string make_temp_dir(const std::string& tag);
// Writes `content` to `path` (creating parent folders); false on failure.
bool write_file(const std::string& path, const std::string& content);
// The whole content of `path`; empty when it cannot be read.
std::string read_file(const std::string& path);

}  // namespace ale::test

// In a TEST body: declares `std::string var` = data_path(relative), or skips (fails in CI) when
// that file or folder does not exist.
#define ALE_REQUIRE_DATA(var, relative)                                                        \
  const std::string var = ::ale::test::data_path(relative);                                    \
  do {                                                                                         \
    if (!::ale::test::path_exists(var)) {                                                      \
      if (::ale::test::running_in_ci()) FAIL() << "CI=true but test data is missing: " << var; \
      GTEST_SKIP() << "test data missing (" << var << "); set ALE_DATA_DIR to ../shared/data"; \
    }                                                                                          \
  } while (0)

namespace ale::test {
bool path_exists(const std::string& path);
}
