// What writing one frame as PNG costs with each encoder setting the recorder could use: the
// median and the slowest of N writes (ms) and the file's size, for the frames given (a EuRoC
// frame, a rendered one...). The recorder's default is level 1 with the up filter.
//
//   ale_png_write_bench OUT_DIR REPEATS FRAME.png...
#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "core/io/image_io.h"

int main(int argc, char** argv) {
  using namespace ale;
  if (argc < 4 || std::atoi(argv[2]) < 1) {
    std::fprintf(stderr, "usage: %s OUT_DIR REPEATS FRAME.png...\n", argv[0]);
    return 2;
  }
  const std::string out = std::string(argv[1]) + "/ale_png_write_bench.png";
  const int repeats = std::atoi(argv[2]);
  struct Setting {
    const char* name;
    io::PngWriteOptions options;
  };
  const Setting settings[] = {{"level0_up", {0, false}},  {"level1_up", {1, false}},     {"level1_adaptive", {1, true}},
                              {"level3_up", {3, false}},  {"default_adaptive", {-1, true}}};
  for (int f = 3; f < argc; ++f) {
    GrayImage frame;
    if (Status s = io::read_gray(argv[f], frame); !s.ok()) {
      std::fprintf(stderr, "%s\n", s.to_string().c_str());
      return 1;
    }
    for (const Setting& setting : settings) {
      std::vector<double> ms;
      for (int r = 0; r < repeats; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        if (Status s = io::write_png(out, frame.view(), setting.options); !s.ok()) {
          std::fprintf(stderr, "%s\n", s.to_string().c_str());
          return 1;
        }
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      }
      std::sort(ms.begin(), ms.end());
      struct stat st {};
      ::stat(out.c_str(), &st);
      std::printf("%s %dx%d %s median_ms=%.2f max_ms=%.2f bytes=%lld raw_bytes=%d\n", argv[f], frame.width, frame.height,
                  setting.name, ms[ms.size() / 2], ms.back(), static_cast<long long>(st.st_size),
                  frame.width * frame.height);
    }
  }
  std::remove(out.c_str());
  return 0;
}
