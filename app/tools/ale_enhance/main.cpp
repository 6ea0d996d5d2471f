// ale-enhance: runs the lighting-adaptive enhancement on image files or dataset folders, writes
// the enhanced frame and a before/after picture per input frame, and prints one line per frame:
//   <path> class=<c> mean=<m> sigma=<s> gamma=<g> clip=<c> median=<m> tiles=<x>x<y> negative=<0|1>
// Folders are read as EuRoC/TUM datasets when they are one, else as a folder of images; the
// grading's hysteresis runs across the frames of one input and restarts for the next.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "core/enhance/enhancer.h"
#include "hal/replay/dataset.h"
#include "core/io/image_io.h"

namespace {

namespace fs = std::filesystem;
using ale::GrayImage;
using ale::Status;

struct Options {
  std::string out_dir = "ale-enhance-out";
  bool write = true;
  double gain = 1.0;  // multiply the input by this first (e.g. 1.65 for the article's bright test)
  std::vector<std::string> inputs;
};

void usage(std::FILE* f) {
  std::fprintf(f,
               "usage: ale-enhance [--out DIR] [--no-write] [--gain F] INPUT...\n"
               "  INPUT     an image (PNG/JPEG), a EuRoC/TUM dataset folder or a folder of images\n"
               "  --out     where to write <name>.enhanced.png and <name>.compare.png (default ale-enhance-out)\n"
               "  --no-write  only print the per-frame line\n"
               "  --gain F  brighten (F > 1) or darken (F < 1) each input first, saturating\n");
}

bool parse(int argc, char** argv, Options& o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      usage(stdout);
      std::exit(0);
    } else if (a == "--out" && i + 1 < argc) {
      o.out_dir = argv[++i];
    } else if (a == "--no-write") {
      o.write = false;
    } else if (a == "--gain" && i + 1 < argc) {
      char* end = nullptr;
      o.gain = std::strtod(argv[++i], &end);
      if (end == argv[i] || *end != '\0' || !(o.gain > 0.0 && o.gain < 100.0)) {
        std::fprintf(stderr, "ale-enhance: --gain wants a number in (0, 100), got '%s'\n", argv[i]);
        return false;
      }
    } else if (!a.empty() && a[0] == '-') {
      std::fprintf(stderr, "ale-enhance: unknown option '%s'\n", a.c_str());
      return false;
    } else {
      o.inputs.push_back(a);
    }
  }
  if (o.inputs.empty()) {
    usage(stderr);
    return false;
  }
  return true;
}

// The frame files of one input: itself, a dataset's frames, or a folder's images (sorted).
Status list_frames(const std::string& input, std::vector<std::string>& frames) {
  frames.clear();
  std::error_code ec;
  if (!fs::exists(input, ec)) return ale::not_found(input + ": no such file or folder");
  if (!fs::is_directory(input, ec)) {
    frames.push_back(input);
    return {};
  }
  auto dataset = ale::replay::open_dataset(input);
  if (dataset.ok()) {
    for (const auto& f : dataset->frames) frames.push_back(f.path);
    return {};
  }
  for (fs::directory_iterator it(input, ec), end; !ec && it != end; it.increment(ec)) {
    std::string ext = it->path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (it->is_regular_file() && (ext == ".png" || ext == ".jpg" || ext == ".jpeg")) frames.push_back(it->path().string());
  }
  if (ec) return ale::io_error(input + ": cannot list folder: " + ec.message());
  if (frames.empty())
    return ale::not_found(input + ": neither a dataset (" + dataset.status().message() + ") nor a folder with images");
  std::sort(frames.begin(), frames.end());
  return {};
}

// "<parent>_<stem>" keeps frames of different folders (webcams) apart in one output folder.
std::string output_name(const std::string& path) {
  const fs::path p(path);
  const std::string parent = p.parent_path().filename().string();
  return (parent.empty() ? "" : parent + "_") + p.stem().string();
}

Status write_outputs(const Options& o, const std::string& path, const GrayImage& before, const GrayImage& after) {
  const std::string base = (fs::path(o.out_dir) / output_name(path)).string();
  ALE_RETURN_IF_ERROR(ale::io::write_png(base + ".enhanced.png", after.view()));
  constexpr int kGap = 8;
  GrayImage side(2 * before.width + kGap, before.height, 0);
  for (int y = 0; y < before.height; ++y) {
    std::copy_n(before.view().row(y), before.width, side.view().row(y));
    std::copy_n(after.view().row(y), after.width, side.view().row(y) + before.width + kGap);
  }
  return ale::io::write_png(base + ".compare.png", side.view());
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (!parse(argc, argv, o)) return 2;
  if (o.write) {
    std::error_code ec;
    fs::create_directories(o.out_dir, ec);
    if (ec) {
      std::fprintf(stderr, "ale-enhance: cannot create output folder %s: %s\n", o.out_dir.c_str(), ec.message().c_str());
      return 1;
    }
  }
  ale::enhance::FrameEnhancer enhancer;
  int failures = 0;
  int frames_done = 0;
  GrayImage before;
  GrayImage after;
  std::vector<std::string> frames;
  for (const std::string& input : o.inputs) {
    Status st = list_frames(input, frames);
    if (!st.ok()) {
      std::fprintf(stderr, "ale-enhance: %s\n", st.to_string().c_str());
      ++failures;
      continue;
    }
    enhancer.reset();
    for (const std::string& path : frames) {
      st = ale::io::read_gray(path, before);
      if (st.ok() && o.gain != 1.0) {
        for (auto& v : before.pixels) v = static_cast<std::uint8_t>(std::min(255.0, std::round(v * o.gain)));
      }
      ale::enhance::EnhanceReport r;
      if (st.ok()) {
        if (after.width != before.width || after.height != before.height) after = GrayImage(before.width, before.height);
        st = enhancer.process(before.view(), after.view(), r);
      }
      if (st.ok() && o.write) st = write_outputs(o, path, before, after);
      if (!st.ok()) {
        std::fprintf(stderr, "ale-enhance: %s: %s\n", path.c_str(), st.to_string().c_str());
        ++failures;
        continue;
      }
      ++frames_done;
      std::printf("%s class=%s mean=%.2f sigma=%.2f gamma=%.3f clip=%.3f median=%d tiles=%dx%d negative=%d\n",
                  path.c_str(), ale::to_string(r.brightness), r.mean, r.sigma, r.gamma, r.clip, r.median, r.tiles_x,
                  r.tiles_y, r.negative ? 1 : 0);
    }
  }
  std::fflush(stdout);
  if (failures > 0) std::fprintf(stderr, "ale-enhance: %d of the inputs failed (%d frames done)\n", failures, frames_done);
  return failures > 0 ? 1 : 0;
}
