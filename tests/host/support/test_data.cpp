#include "tests/host/support/test_data.h"

#include <sys/stat.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

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

bool path_exists(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0;
}

std::string make_temp_dir(const std::string& tag) {
  namespace fs = std::filesystem;
  std::string pattern = (fs::temp_directory_path() / ("ale-test-" + tag + "-XXXXXX")).string();
  char* made = ::mkdtemp(pattern.data());
  return made != nullptr ? std::string(made) : std::string();
}

bool write_file(const std::string& path, const std::string& content) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(fs::path(path).parent_path(), ec);
  std::ofstream out(path, std::ios::binary);
  out << content;
  return static_cast<bool>(out);
}

}  // namespace ale::test
