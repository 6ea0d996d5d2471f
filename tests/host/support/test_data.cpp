#include "tests/host/support/test_data.h"

#include <sys/stat.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace ale::test {

std::string data_root() {
  const char* env = std::getenv("ALE_DATA_DIR");
  if (env != nullptr && *env != '\0') return env;
  return ALE_SHARED_DATA_DIR;
}

std::string data_path(const std::string& relative) { return data_root() + "/" + relative; }

bool running_in_ci() {
  const char* env = std::getenv("CI");
  return env != nullptr && std::string(env) == "true";
}

bool reduced_run() {
  const char* env = std::getenv("ALE_TEST_REDUCED");
  return env != nullptr && std::string(env) == "1";
}

bool path_exists(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0;
}

namespace {

// Removes the folders make_temp_dir() made when the test binary exits (a failing test included),
// so runs do not pile fixtures up in /tmp. ALE_KEEP_TEST_DIRS=1 keeps them for inspection.
class TempDirs {
 public:
  ~TempDirs() {
    const char* keep = std::getenv("ALE_KEEP_TEST_DIRS");
    if (keep != nullptr && std::string(keep) == "1") return;
    std::error_code ec;
    for (const std::string& d : dirs_) std::filesystem::remove_all(d, ec);
  }
  void add(const std::string& d) { dirs_.push_back(d); }

 private:
  std::vector<std::string> dirs_;
};

TempDirs& temp_dirs() {
  static TempDirs dirs;
  return dirs;
}

}  // namespace

std::string make_temp_dir(const std::string& tag) {
  namespace fs = std::filesystem;
  std::string pattern = (fs::temp_directory_path() / ("ale-test-" + tag + "-XXXXXX")).string();
  char* made = ::mkdtemp(pattern.data());
  if (made == nullptr) return std::string();
  temp_dirs().add(made);
  return made;
}

bool write_file(const std::string& path, const std::string& content) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(fs::path(path).parent_path(), ec);
  std::ofstream out(path, std::ios::binary);
  out << content;
  return static_cast<bool>(out);
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace ale::test
