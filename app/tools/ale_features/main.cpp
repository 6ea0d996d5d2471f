// ale-features: run the ORB front end on images, print counts, write keypoint overlays.
//
//   ale-features [--mode ale|baseline|clahe] [--out DIR] [--features N] [--levels N]
//                [--repeat N] [--crop WxH] IMAGE...
//   ale-features --article [--data DIR] [--out DIR]
//
// One line per image and mode: `<path> mode=<mode> features=<n> class=<c> levels=<n0,n1,...>`.
// --article reproduces the article's single-frame experiment: a normal EuRoC V1_01 frame, the same
// frame brightened by 65 % (v * 1.65, saturated), and the dark EuRoC frame, each with baseline,
// CLAHE-everywhere and ALE. --repeat runs the extraction N times per image (for instruction
// counts: the difference between two repeat counts cancels start-up and decoding); --crop keeps
// the top-left WxH pixels (e.g. 640x480 of a 752x480 EuRoC frame).
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "core/features/orb.h"
#include "core/frontend/frame_path.h"
#include "core/io/image_io.h"

namespace {

using ale::GrayImage;
using ale::Status;
using namespace ale::features;

struct Options {
  std::vector<ExtractorMode> modes{ExtractorMode::kAle};
  std::string out_dir;
  std::string data_dir;
  int features = 1000;
  int levels = 8;
  int repeat = 1;
  int crop_w = 0;  // 0: whole image
  int crop_h = 0;
  bool article = false;
  std::vector<std::string> images;
};

int usage(const char* argv0) {
  std::fprintf(stderr,
               "usage: %s [--mode ale|baseline|clahe|all] [--out DIR] [--features N] [--levels N] [--repeat N] "
               "IMAGE...\n       %s --article [--data DIR] [--out DIR]\n",
               argv0, argv0);
  return 2;
}

bool parse_int(const char* s, int lo, int hi, int& out) {
  char* end = nullptr;
  const long v = std::strtol(s, &end, 10);
  if (end == s || *end != '\0' || v < lo || v > hi) return false;
  out = static_cast<int>(v);
  return true;
}

std::string base_name(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  const std::size_t dot = name.find_last_of('.');
  return dot == std::string::npos ? name : name.substr(0, dot);
}

// The input in grey with each keypoint as a circle of its size, coloured by level, and a tick
// for its orientation.
Status write_overlay(const std::string& path, const GrayImage& image, const std::vector<Keypoint>& kps) {
  cv::Mat grey(image.height, image.width, CV_8UC1, const_cast<std::uint8_t*>(image.pixels.data()));
  cv::Mat rgb;
  cv::cvtColor(grey, rgb, cv::COLOR_GRAY2RGB);
  static const cv::Scalar kColours[] = {{255, 60, 60}, {255, 160, 0}, {230, 230, 0}, {60, 220, 60},
                                        {0, 220, 220}, {60, 120, 255}, {170, 80, 255}, {255, 80, 200}};
  for (const Keypoint& k : kps) {
    const cv::Scalar& c = kColours[static_cast<std::size_t>(k.level) % 8u];
    const cv::Point2f centre(k.x, k.y);
    const float r = std::max(2.0f, 0.12f * k.size);
    cv::circle(rgb, centre, static_cast<int>(r + 0.5f), c, 1, cv::LINE_AA);
    const float a = k.angle_deg * static_cast<float>(CV_PI / 180.0);
    cv::line(rgb, centre, centre + cv::Point2f(r * std::cos(a), r * std::sin(a)), c, 1, cv::LINE_AA);
  }
  return ale::io::write_png_rgb(path, rgb.data, rgb.cols, rgb.rows, static_cast<int>(rgb.step));
}

// Extracts with `mode` and prints the line; writes an overlay when out_dir is set.
bool run(const Options& opt, ExtractorMode mode, const std::string& label, const GrayImage& image) {
  ExtractorConfig cfg;
  cfg.mode = mode;
  cfg.num_features = opt.features;
  cfg.num_levels = opt.levels;
  ale::frontend::FramePath ex;
  Status st = ex.configure(cfg);
  std::vector<Keypoint> kps;
  std::vector<Descriptor> desc;
  for (int i = 0; st.ok() && i < opt.repeat; ++i) {
    ex.reset();  // each repeat grades the frame afresh
    st = ex.extract(image.view(), kps, desc);
  }
  if (!st.ok()) {
    std::fprintf(stderr, "%s: %s\n", label.c_str(), st.to_string().c_str());
    return false;
  }
  const ExtractionStats& s = ex.stats();
  std::string levels;
  int retry = 0, low = 0, empty = 0, skipped = 0;
  for (int l = 0; l < s.levels; ++l) {
    levels += (l ? "," : "") + std::to_string(s.level[static_cast<std::size_t>(l)].kept);
    retry += s.level[static_cast<std::size_t>(l)].cells_retry;
    low += s.level[static_cast<std::size_t>(l)].cells_low;
    empty += s.level[static_cast<std::size_t>(l)].cells_empty;
    skipped += s.level[static_cast<std::size_t>(l)].cells_skipped;
  }
  // Only ALE grades the frame.
  const std::string graded = mode == ExtractorMode::kAle ? std::string(" class=") + ale::to_string(s.brightness) : "";
  std::printf("%s mode=%s features=%d levels=%s cells_retry=%d cells_low=%d cells_empty=%d retries_skipped=%d%s\n",
              label.c_str(), to_string(mode), s.total, levels.c_str(), retry, low, empty, skipped, graded.c_str());
  if (!opt.out_dir.empty()) {
    const std::string path = opt.out_dir + "/" + base_name(label) + "_" + to_string(mode) + ".png";
    const Status w = write_overlay(path, image, kps);
    if (!w.ok()) {
      std::fprintf(stderr, "%s\n", w.to_string().c_str());
      return false;
    }
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  Options opt;
  const char* env_data = std::getenv("ALE_DATA_DIR");
  opt.data_dir = env_data != nullptr ? env_data : "../shared/data";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "--mode" && has_value) {
      const std::string m = argv[++i];
      if (m == "all") {
        opt.modes = {ExtractorMode::kBaseline, ExtractorMode::kClahe, ExtractorMode::kAle};
      } else {
        const auto parsed = parse_extractor_mode(m);
        if (!parsed.ok()) {
          std::fprintf(stderr, "--mode: %s\n", parsed.status().message().c_str());
          return 2;
        }
        opt.modes = {*parsed};
      }
    } else if (a == "--out" && has_value) {
      opt.out_dir = argv[++i];
    } else if (a == "--data" && has_value) {
      opt.data_dir = argv[++i];
    } else if (a == "--features" && has_value) {
      if (!parse_int(argv[++i], 1, 100000, opt.features)) return usage(argv[0]);
    } else if (a == "--levels" && has_value) {
      if (!parse_int(argv[++i], 1, kMaxLevels, opt.levels)) return usage(argv[0]);
    } else if (a == "--repeat" && has_value) {
      if (!parse_int(argv[++i], 0, 1000000, opt.repeat)) return usage(argv[0]);
    } else if (a == "--crop" && has_value) {
      if (std::sscanf(argv[++i], "%dx%d", &opt.crop_w, &opt.crop_h) != 2 || opt.crop_w < 1 || opt.crop_h < 1)
        return usage(argv[0]);
    } else if (a == "--article") {
      opt.article = true;
    } else if (!a.empty() && a[0] == '-') {
      return usage(argv[0]);
    } else {
      opt.images.push_back(a);
    }
  }
  if (opt.article == !opt.images.empty()) return usage(argv[0]);
  if (!opt.out_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(opt.out_dir, ec);
    if (ec) {
      std::fprintf(stderr, "ale-features: cannot create output folder %s: %s\n", opt.out_dir.c_str(),
                   ec.message().c_str());
      return 1;
    }
  }

  bool ok = true;
  if (opt.article) {
    const std::string normal_path =
        opt.data_dir + "/euroc_v101_micro/mav0/cam0/data/1403715273262142976.png";
    const std::string dark_path = opt.data_dir + "/lighting/dark_frame/euroc_dark.png";
    GrayImage normal, dark;
    for (const auto& [path, img] : {std::pair<const std::string&, GrayImage&>{normal_path, normal},
                                    std::pair<const std::string&, GrayImage&>{dark_path, dark}}) {
      const Status st = ale::io::read_gray(path, img);
      if (!st.ok()) {
        std::fprintf(stderr, "%s\n", st.to_string().c_str());
        return 1;
      }
    }
    GrayImage bright = normal;
    for (auto& v : bright.pixels) v = static_cast<std::uint8_t>(std::min(255, (v * 165 + 50) / 100));
    const std::pair<std::string, const GrayImage*> frames[] = {
        {"euroc_normal", &normal}, {"euroc_brightened65", &bright}, {"euroc_dark", &dark}};
    for (const auto& [label, img] : frames)
      for (ExtractorMode m : {ExtractorMode::kBaseline, ExtractorMode::kClahe, ExtractorMode::kAle})
        ok = run(opt, m, label, *img) && ok;
    return ok ? 0 : 1;
  }
  for (const std::string& path : opt.images) {
    GrayImage img;
    const Status st = ale::io::read_gray(path, img);
    if (!st.ok()) {
      std::fprintf(stderr, "%s\n", st.to_string().c_str());
      ok = false;
      continue;
    }
    if (opt.crop_w > 0) {
      if (opt.crop_w > img.width || opt.crop_h > img.height) {
        std::fprintf(stderr, "%s: %dx%d is smaller than --crop %dx%d\n", path.c_str(), img.width, img.height,
                     opt.crop_w, opt.crop_h);
        ok = false;
        continue;
      }
      GrayImage cropped(opt.crop_w, opt.crop_h);
      ale::copy_pixels(img.view().sub(0, 0, opt.crop_w, opt.crop_h), cropped.view());
      img = std::move(cropped);
    }
    for (ExtractorMode m : opt.modes) ok = run(opt, m, path, img) && ok;
  }
  return ok ? 0 : 1;
}
