// The real frames the enhancement tests run on (../shared/data), listed once.
#pragma once

#include <algorithm>
#include <dirent.h>
#include <string>
#include <vector>

namespace ale::test {

// Sorted *.png / *.jpg files of a folder (empty when it cannot be read).
inline std::vector<std::string> image_files(const std::string& dir) {
  std::vector<std::string> out;
  if (DIR* d = opendir(dir.c_str())) {
    while (dirent* e = readdir(d)) {
      const std::string name = e->d_name;
      const auto dot = name.rfind('.');
      if (dot == std::string::npos) continue;
      const std::string ext = name.substr(dot);
      if (ext == ".png" || ext == ".jpg") out.push_back(dir + "/" + name);
    }
    closedir(d);
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
