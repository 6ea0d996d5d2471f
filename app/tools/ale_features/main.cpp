// ale-features: run the ORB front end on images, print counts, write keypoint overlays.
//
//   ale-features [--mode ale|baseline|clahe] [--out DIR] [--features N] [--levels N]
//                [--repeat N] [--crop WxH] IMAGE...
//   ale-features --article [--data DIR] [--out DIR]
//   ale-features --match A.png B.png [--mode M|all] [--features N] [--levels N]
//   ale-features --match-report [--mode M|all] [--gaps 1,3,5] [--frames N] DIR...
//
// One line per image and mode: `<path> mode=<mode> features=<n> class=<c> levels=<n0,n1,...>`.
// --article reproduces the article's single-frame experiment: a normal EuRoC V1_01 frame, the same
// frame brightened by 65 % (v * 1.65, saturated), and the dark EuRoC frame, each with baseline,
// CLAHE-everywhere and ALE. --repeat runs the extraction N times per image (for instruction
// counts: the difference between two repeat counts cancels start-up and decoding); --crop keeps
// the top-left WxH pixels (e.g. 640x480 of a 752x480 EuRoC frame).
//
// --match extracts A, then B (in that order through one frame path per mode, so B is graded with
// A's class held, as in a sequence) and prints per mode
// `mode=<m> keypoints_a=.. keypoints_b=.. matches=.. inliers=..` (core/features/pair_match.h:
// mutual nearest neighbours with the ratio test and Hamming gate, fundamental-matrix RANSAC at
// 1 px, seeded). Without --mode every mode runs. --match-report does the same over sequences
// (EuRoC folders as ale-render writes them, or folders of PNGs), pairs `gap` frames apart:
// `<dir> mode=<m> gap=<g> pairs=.. keypoints=.. matches=.. inliers=..` (means over the pairs).
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
#include "core/features/pair_match.h"
#include "core/frontend/frame_path.h"
#include "core/frontend/sequence_match.h"
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
  bool match = false;         // --match A B
  bool match_report = false;  // --match-report DIR...
  bool mode_given = false;
  bool with_article = false;  // --match/--match-report: also ALE as the article describes it
  std::vector<std::pair<std::string, std::string>> settings;  // --set key=value
  std::vector<int> gaps{1, 3, 5};
  int max_frames = 0;  // --match-report: 0 = every frame
  std::vector<std::string> images;
};

int usage(const char* argv0) {
  std::fprintf(stderr,
               "usage: %s [--mode ale|baseline|off|clahe|he|gamma|all] [--out DIR] [--features N] [--levels N] "
               "[--repeat N] IMAGE...\n       %s --article [--data DIR] [--out DIR]\n"
               "       %s --match A.png B.png [--mode M|all] [--features N] [--levels N]\n"
               "       %s --match-report [--mode M|all] [--gaps 1,3,5] [--frames N] DIR...\n",
               argv0, argv0, argv0, argv0);
  return 2;
}

constexpr ExtractorMode kAllModes_[] = {ExtractorMode::kBaseline, ExtractorMode::kClahe, ExtractorMode::kHe,
                                        ExtractorMode::kGamma, ExtractorMode::kAle};
const std::vector<ExtractorMode> kAllModes(std::begin(kAllModes_), std::end(kAllModes_));

bool parse_int(const char* s, int lo, int hi, int& out) {
  char* end = nullptr;
  const long v = std::strtol(s, &end, 10);
  if (end == s || *end != '\0' || v < lo || v > hi) return false;
  out = static_cast<int>(v);
  return true;
}

// "1,3,5": gaps of at least 1 frame.
bool parse_gaps(const char* s, std::vector<int>& out) {
  out.clear();
  std::string text = s;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    int g = 0;
    if (!parse_int(text.substr(start, comma - start).c_str(), 1, 100000, g)) return false;
    out.push_back(g);
    start = comma + 1;
  }
  return !out.empty();
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

// The configuration of `mode` (ALE as the article describes it when `article`), with the options.
// The --set values were checked when parsed.
ExtractorConfig config_for(const Options& opt, ExtractorMode mode, bool article = false) {
  ExtractorConfig cfg = article ? article_config() : ExtractorConfig{};
  cfg.mode = mode;
  cfg.num_features = opt.features;
  cfg.num_levels = opt.levels;
  for (const auto& [key, value] : opt.settings) (void)ale::set_field(extractor_config_table(), &cfg, key, value, "--set");
  return cfg;
}

// The runs of --match / --match-report: the modes, then the article's ALE.
struct ModeRun {
  ExtractorMode mode;
  bool article;
  const char* label() const { return article ? "article" : to_string(mode); }
};
std::vector<ModeRun> mode_runs(const Options& opt) {
  std::vector<ModeRun> runs;
  for (ExtractorMode m : opt.modes) runs.push_back({m, false});
  if (opt.with_article) runs.push_back({ExtractorMode::kAle, true});
  return runs;
}

// Extracts with `mode` and prints the line; writes an overlay when out_dir is set.
bool run(const Options& opt, ExtractorMode mode, const std::string& label, const GrayImage& image) {
  ale::frontend::FramePath ex;
  Status st = ex.configure(config_for(opt, mode));
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

// --match A B: exit 0, 1 for unreadable or mismatched images or a failed extraction.
int match_images(const Options& opt) {
  GrayImage frames[2];
  for (int k = 0; k < 2; ++k) {
    const Status st = ale::io::read_gray(opt.images[static_cast<std::size_t>(k)], frames[k]);
    if (!st.ok()) {
      std::fprintf(stderr, "ale-features --match: %s\n", st.to_string().c_str());
      return 1;
    }
  }
  if (frames[0].width != frames[1].width || frames[0].height != frames[1].height) {
    std::fprintf(stderr, "ale-features --match: %s is %dx%d but %s is %dx%d: the frames must have one size\n",
                 opt.images[0].c_str(), frames[0].width, frames[0].height, opt.images[1].c_str(), frames[1].width,
                 frames[1].height);
    return 1;
  }
  const std::vector<GrayImage> pair{frames[0], frames[1]};
  for (const ModeRun& m : mode_runs(opt)) {
    const auto figures =
        ale::frontend::match_sequence(pair, config_for(opt, m.mode, m.article), {1}, PairMatchParams{});
    if (!figures.ok()) {
      std::fprintf(stderr, "ale-features --match: mode %s: %s\n", m.label(), figures.status().to_string().c_str());
      return 1;
    }
    const PairMatchFigures& f = figures->front().pairs.front();
    std::printf("mode=%s keypoints_a=%d keypoints_b=%d matches=%d inliers=%d\n", m.label(), f.keypoints_a,
                f.keypoints_b, f.matches, f.inliers);
  }
  return 0;
}

// The frames of a sequence folder: DIR/mav0/cam0/data/*.png (EuRoC, ale-render) or DIR/*.png, in
// name order (timestamps), at most `max_frames` (0: all).
ale::Status read_sequence(const std::string& dir, int max_frames, std::vector<GrayImage>& frames) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path euroc = fs::path(dir) / "mav0" / "cam0" / "data";
  const fs::path folder = fs::is_directory(euroc, ec) ? euroc : fs::path(dir);
  if (!fs::is_directory(folder, ec)) return ale::not_found(dir + ": not a folder");
  std::vector<std::string> files;
  for (const auto& entry : fs::directory_iterator(folder, ec))
    if (entry.is_regular_file() && entry.path().extension() == ".png") files.push_back(entry.path().string());
  if (ec) return ale::io_error(folder.string() + ": cannot list: " + ec.message());
  std::sort(files.begin(), files.end());
  if (max_frames > 0 && static_cast<int>(files.size()) > max_frames) files.resize(static_cast<std::size_t>(max_frames));
  if (files.size() < 2) return ale::not_found(folder.string() + ": fewer than two .png frames");
  frames.resize(files.size());
  for (std::size_t i = 0; i < files.size(); ++i) ALE_RETURN_IF_ERROR(ale::io::read_gray(files[i], frames[i]));
  return {};
}

int match_report(const Options& opt) {
  bool ok = true;
  for (const std::string& dir : opt.images) {
    std::vector<GrayImage> frames;
    Status st = read_sequence(dir, opt.max_frames, frames);
    if (!st.ok()) {
      std::fprintf(stderr, "ale-features --match-report: %s\n", st.to_string().c_str());
      ok = false;
      continue;
    }
    for (const ModeRun& m : mode_runs(opt)) {
      const auto figures =
          ale::frontend::match_sequence(frames, config_for(opt, m.mode, m.article), opt.gaps, PairMatchParams{});
      if (!figures.ok()) {
        std::fprintf(stderr, "%s mode=%s: %s\n", dir.c_str(), m.label(), figures.status().to_string().c_str());
        ok = false;
        continue;
      }
      for (const ale::frontend::GapFigures& g : *figures)
        std::printf("%s mode=%s gap=%d pairs=%zu keypoints=%.1f matches=%.1f inliers=%.1f\n", dir.c_str(),
                    m.label(), g.gap, g.pairs.size(), g.mean_keypoints(), g.mean_matches(), g.mean_inliers());
    }
  }
  return ok ? 0 : 1;
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
      opt.mode_given = true;
      opt.with_article = false;
      if (m == "all") {
        opt.modes = kAllModes;
        opt.with_article = true;  // used by --match and --match-report only
      } else if (m == "article") {
        opt.modes.clear();
        opt.with_article = true;
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
    } else if (a == "--set" && has_value) {
      const std::string kv = argv[++i];
      const std::size_t eq = kv.find('=');
      ExtractorConfig probe;
      const Status st = eq == std::string::npos
                            ? ale::invalid_argument("--set " + kv + ": expected key=value")
                            : ale::set_field(extractor_config_table(), &probe, kv.substr(0, eq), kv.substr(eq + 1), "--set");
      if (!st.ok()) {
        std::fprintf(stderr, "ale-features: --set: %s\n", st.message().c_str());
        return 2;
      }
      opt.settings.emplace_back(kv.substr(0, eq), kv.substr(eq + 1));
    } else if (a == "--match") {
      opt.match = true;
    } else if (a == "--match-report") {
      opt.match_report = true;
    } else if (a == "--gaps" && has_value) {
      if (!parse_gaps(argv[++i], opt.gaps)) return usage(argv[0]);
    } else if (a == "--frames" && has_value) {
      if (!parse_int(argv[++i], 2, 1000000, opt.max_frames)) return usage(argv[0]);
    } else if (!a.empty() && a[0] == '-') {
      return usage(argv[0]);
    } else {
      opt.images.push_back(a);
    }
  }
  if (opt.match && opt.match_report) return usage(argv[0]);
  if (opt.match || opt.match_report) {
    if (opt.article || (opt.match && opt.images.size() != 2) || opt.images.empty()) return usage(argv[0]);
    if (!opt.mode_given) {
      opt.modes = kAllModes;
      opt.with_article = true;
    }
    if (opt.modes.empty() && !opt.with_article) return usage(argv[0]);
    return opt.match ? match_images(opt) : match_report(opt);
  }
  if (opt.article == !opt.images.empty() || opt.modes.empty()) return usage(argv[0]);
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
