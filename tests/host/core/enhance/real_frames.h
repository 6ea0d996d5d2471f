// The real frames the enhancement tests run on (../shared/data), listed once.
#pragma once

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

namespace ale::test {

// Sorted *.png / *.jpg files of a folder (empty when it cannot be read).
inline std::vector<std::string> image_files(const std::string& dir) {
  namespace fs = std::filesystem;
  std::vector<std::string> out;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string ext = it->path().extension().string();
    if (ext == ".png" || ext == ".jpg") out.push_back(it->path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

// Every `step`-th element, starting with the first.
inline std::vector<std::string> every(const std::vector<std::string>& v, std::size_t step) {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < v.size(); i += step) out.push_back(v[i]);
  return out;
}

inline const char* const kWebcams[] = {"chamonix", "courbevoie", "stlouis"};

}  // namespace ale::test
