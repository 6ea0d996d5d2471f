// ale-render: renders sweeper-camera sequences of a textured room under changing light, in the
// EuRoC ASL layout with ground truth (docs/rendering.md), or checkerboard views through a known
// lens for camera calibration (docs/calibration.md).
//
//   ale-render --out DIR [--trajectory loop|square|lanes|FILE] [--lanes N --lane-width M --lane-length M] [--frames N | --duration D] [--fps F]
//              [--turn-rate DEG_PER_S] [--room WxDxH | --scene twin] [--blackout START,DURATION]... [--kidnap AT,TO,GAP]...
//              [--start S] [--light PROFILE] [--seed S] [--width W --height H] [--textures DIR]
//              [--supersample K] [--max-gain G] [--read-noise E] [--texture-seed N]
//              [--noise-model NAME] [--full-well E] [--fpn-gain PCT] [--fpn-offset E]
//              [--vignetting-power N] [--row-noise E] [--jpeg-quality Q]
//              [--lens ideal|radtan|fisheye | --camera FILE.yaml] [--overwrite]
//              [--odometry-noise none|normal|harsh] [--odometry-seed N] [--odometry-rate HZ]
//              [--odometry-clock-offset-ms MS]
//   ale-render --checkerboard COLSxROWS --out DIR [--square M] [--views N] [--noise G]
//              [--lens L | --camera FILE.yaml] [--seed S] [--width W --height H] [--supersample K]
//
// Exit status: 0 ok, 1 bad data or a failed write, 2 bad usage (a trajectory file that cannot be
// used counts as usage).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "app/tools/ale_render/euroc_writer.h"
#include "app/tools/lib/eval/trajectory.h"
#include "app/tools/lib/render/checkerboard.h"
#include "app/tools/lib/render/noise_model.h"
#include "app/tools/lib/render/renderer.h"
#include "app/tools/lib/render/sensor_yaml.h"
#include "core/io/image_io.h"
#include "core/base/rng.h"
#include "hal/replay/dataset.h"

namespace {

namespace r = ale::render;
using ale::Result;
using ale::Status;

constexpr int kExitData = 1;
constexpr int kExitUsage = 2;
// How far a recorded flight stays from the hall's furniture, metres.
constexpr float kFurnitureClearance = 0.8f;

constexpr const char* kUsage =
    "usage: ale-render --out DIR [options]\n"
    "  --trajectory T   loop (default), square, lanes, or FILE: a recorded body trajectory (TUM or\n"
    "                   EuRoC state CSV, e.g. EuRoC ground truth) followed in 6-DoF with EuRoC's\n"
    "                   cam0 mounting, in a hall sized around it; groundtruth.txt is the camera\n"
    "  --lanes N --lane-width M --lane-length M   the lanes route: N lanes (default 6) M metres\n"
    "                   apart (0.3), each M long (3.0), turns of 90 degrees in place between them\n"
    "  --turn-rate R    degrees per second of the turns in place of square and lanes (default 60)\n"
    "  --room WxDxH     a room of that size in metres (W, D 3..30, H 2..5) for loop, square and lanes:\n"
    "                   a hall with furniture kept clear of the route, laid out by --texture-seed\n"
    "                   (default: the 6 x 5 x 2.5 m living room)\n"
    "  --scene twin     two copies of the living room side by side (12 x 5 m, a partition with an\n"
    "                   opening, the same textures): the route drives the square in one, goes\n"
    "                   through the opening and drives it in the other (no --trajectory)\n"
    "  --blackout S,D   all light off (the sensor sees only noise) from S seconds after the first\n"
    "                   frame for D seconds; may be given several times\n"
    "  --kidnap A,T,G   when the trajectory's time reaches A seconds the camera jumps to its pose at\n"
    "                   T (< A, a place already seen) and drives on from there; the timestamps go\n"
    "                   on after G seconds without frames; several in the order they happen\n"
    "  --frames N       frames to render (default 300; a FILE: to its end)\n"
    "  --duration D     seconds to render instead of --frames: round(D x fps) frames\n"
    "  --fps F          frame rate (default 30)\n"
    "  --start S        seconds into the trajectory for the first frame (default 0)\n"
    "  --light P        bright, normal_bright, normal (default), normal_dark, dark, off_on,\n"
    "                   sunlit, dimming\n"
    "  --seed S         sensor noise seed, a whole number (default 1)\n"
    "  --width W --height H   image size (default 640x480)\n"
    "  --textures DIR   photographs (PNG/JPEG) to use instead of procedural textures\n"
    "  --supersample K  rays per pixel K x K, 1..4 (default 2)\n"
    "  --max-gain G     the sensor's largest analogue gain, 1..64 (default 8)\n"
    "  --read-noise E   read noise in electrons rms, 0..100 (default 2.5; small-pixel, harsh: 4)\n"
    "  --noise-model M  the sensor's noise: standard (default), small-pixel (3500 e- full well,\n"
    "                   0.45 x the electrons, 4 e- read noise), fpn (fixed-pattern gain and offset),\n"
    "                   vignetting (cos^4), banding (row noise), jpeg (8x8 block DCT, quality 75),\n"
    "                   harsh (all of them); the values below change the model's\n"
    "  --full-well E    electrons at saturation, 500..200000 (standard 8000, small-pixel 3500)\n"
    "  --fpn-gain P     fpn, harsh: per-pixel gain spread, percent rms 0..50 (default 1.5)\n"
    "  --fpn-offset E   fpn, harsh: per-pixel offset, electrons rms 0..500 (default 6)\n"
    "  --vignetting-power N  vignetting, harsh: illumination cos^N off axis, 0..8 (default 4)\n"
    "  --row-noise E    banding, harsh: per-row offset each frame, electrons rms 0..500 (default 3)\n"
    "  --jpeg-quality Q jpeg, harsh: compression quality 1..100 (default 75)\n"
    "  --texture-seed N seed of the procedural textures, 0..4294967295 (another room's look)\n"
    "  --lens L         the camera's lens: ideal (default; 90 degrees across, no distortion),\n"
    "                   radtan (barrel distortion) or fisheye (equidistant, ~120 degrees across)\n"
    "  --camera FILE    the lens of a sensor.yaml (its resolution replaces --width/--height)\n"
    "  --overwrite      replace an existing DIR/mav0 (checkerboard: DIR's views)\n"
    "the sweeper's wheel odometry (loop, square, lanes, twin; DIR/mav0/odometry0):\n"
    "  --odometry-noise N  none (the truth), normal (default) or harsh: the MCU's errors\n"
    "  --odometry-seed N   seed of the odometry's errors, a whole number (default 1)\n"
    "  --odometry-rate HZ  samples per second, 15..200 (default 50)\n"
    "  --odometry-clock-offset-ms MS  the MCU's clock minus the camera's, -1000..1000 (default 0)\n"
    "checkerboard views (DIR/view_NNN.png, DIR/calibration.yaml: the true lens, DIR/poses.csv):\n"
    "  --checkerboard COLSxROWS  inner corners along a row and a column (e.g. 9x6)\n"
    "  --square M       side of a square in metres (default 0.03)\n"
    "  --views N        views, 1..1000 (default 20)\n"
    "  --noise G        sensor noise in grey levels rms, 0..50 (default 1.5)\n"
    "  (--supersample defaults to 4 here, 1..8)\n";

int usage_error(const std::string& message) {
  std::fprintf(stderr, "ale-render: %s\n%s", message.c_str(), kUsage);
  return kExitUsage;
}

int data_error(const Status& s) {
  std::fprintf(stderr, "ale-render: %s\n", s.message().c_str());
  return kExitData;
}

bool parse_int(const std::string& text, long long lo, long long hi, long long& out) {
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno != 0 || v < lo || v > hi) return false;
  out = v;
  return true;
}

bool parse_double(const std::string& text, double lo, double hi, double& out) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(v) || v < lo || v > hi) return false;
  out = v;
  return true;
}

// `count` numbers separated by `sep` (e.g. "2.5,1" or "8x6x2.6").
bool parse_numbers(const std::string& text, char sep, int count, std::vector<double>& out) {
  out.clear();
  std::size_t pos = 0;
  for (int i = 0; i < count; ++i) {
    const std::size_t end = i + 1 < count ? text.find(sep, pos) : text.size();
    if (end == std::string::npos) return false;
    double d = 0.0;
    if (!parse_double(text.substr(pos, end - pos), -1e9, 1e9, d)) return false;
    out.push_back(d);
    pos = end + 1;
  }
  return true;
}

Status load_photos(const std::string& dir, std::vector<ale::GrayImage>& photos) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return ale::not_found(dir + ": not a folder (--textures)");
  std::vector<std::string> files;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    std::string ext = entry.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (entry.is_regular_file() && (ext == ".png" || ext == ".jpg" || ext == ".jpeg")) files.push_back(entry.path().string());
  }
  if (ec) return ale::io_error(dir + ": cannot list: " + ec.message());
  if (files.empty()) return ale::not_found(dir + ": no .png or .jpg files (--textures)");
  std::sort(files.begin(), files.end());
  for (const std::string& f : files) {
    ale::GrayImage img;
    ALE_RETURN_IF_ERROR(ale::io::read_gray(f, img));
    photos.push_back(std::move(img));
  }
  return {};
}

// --noise-model and the values that change it (docs/rendering.md): the model's parameters into
// `sensor`, then the options'. Returns 0, or the exit status of a usage error naming the option
// (an unknown model, a value out of range, a value the model does not use).
int parse_noise_options(std::map<std::string, std::string>& opt, std::string& model, r::SensorParams& sensor) {
  if (opt.count("--noise-model")) model = opt["--noise-model"];
  if (const Status s = r::apply_noise_model(model, sensor); !s.ok()) return usage_error("--noise-model: " + s.message());
  const r::SensorParams preset = sensor;
  struct Value {
    const char* key;
    double lo, hi, scale;
    double* target;
    bool used;  // by the model
    const char* what;
  };
  double quality = preset.jpeg_quality;
  const bool fixed_pattern = preset.fpn_gain > 0.0 || preset.fpn_offset_e > 0.0;
  const Value values[] = {
      {"--full-well", 500.0, 200000.0, 1.0, &sensor.full_well_e, true, "electrons"},
      {"--fpn-gain", 0.0, 50.0, 0.01, &sensor.fpn_gain, fixed_pattern, "percent rms"},
      {"--fpn-offset", 0.0, 500.0, 1.0, &sensor.fpn_offset_e, fixed_pattern, "electrons rms"},
      {"--vignetting-power", 0.0, 8.0, 1.0, &sensor.vignetting_power,
       preset.vignetting == r::SensorParams::Vignetting::kCosPower, "an exponent of cos"},
      {"--row-noise", 0.0, 500.0, 1.0, &sensor.row_noise_e, preset.row_noise_e > 0.0, "electrons rms"},
      {"--jpeg-quality", 1.0, 100.0, 1.0, &quality, preset.jpeg_quality > 0, "a whole number"},
  };
  for (const Value& v : values) {
    if (!opt.count(v.key)) continue;
    if (!v.used) return usage_error(std::string(v.key) + " does not change --noise-model " + model);
    double d = 0.0;
    char range[160];
    std::snprintf(range, sizeof range, "%s must be %s in %g..%g, not '%s'", v.key, v.what, v.lo, v.hi,
                  opt[v.key].c_str());
    if (!parse_double(opt[v.key], v.lo, v.hi, d)) return usage_error(range);
    if (std::string(v.key) == "--jpeg-quality" && d != std::floor(d)) return usage_error(range);
    *v.target = d * v.scale;
  }
  sensor.jpeg_quality = static_cast<int>(quality);
  return 0;
}

// Text's lines joined by "; ".
std::string one_line(const std::string& text) {
  std::string out;
  for (char c : text) out += c == '\n' ? std::string("; ") : std::string(1, c);
  while (!out.empty() && (out.back() == ' ' || out.back() == ';')) out.pop_back();
  return out;
}

// A recorded trajectory (TUM or EuRoC state CSV) as body poses from its start; `start_ns` gets
// its first timestamp.
Result<std::vector<r::TimedPose>> load_recorded(const std::string& path, std::int64_t& start_ns) {
  Result<ale::eval::Trajectory> t = ale::eval::read_trajectory(path);
  if (!t.ok()) return t.status();
  std::vector<r::TimedPose> out;
  for (const ale::eval::StampedPose& s : t->poses) {
    r::TimedPose p;
    p.t_s = s.t_s;
    p.pose.q_wb = Eigen::Quaterniond(s.R_wb).normalized();
    p.pose.p_wb = s.p_wb;
    out.push_back(p);
  }
  if (out.empty()) return ale::invalid_argument(path + ": no poses");
  // Recorded times have at most microsecond digits; a double holds them only to ~0.2 us.
  start_ns = std::llround(out.front().t_s * 1e6) * 1000;
  return out;
}

// The lens of a sensor.yaml (what ale-slamd reads), at the file's resolution.
Result<r::PinholeCamera> camera_from_yaml(const std::string& path) {
  Result<ale::hal::CameraCalibration> k = ale::replay::read_euroc_sensor_yaml(path);
  if (!k.ok()) return k.status();
  r::PinholeCamera c;
  c.width = k->width;
  c.height = k->height;
  c.fx = k->fx;
  c.fy = k->fy;
  c.cx = k->cx;
  c.cy = k->cy;
  c.distortion = k->distortion_model == ale::hal::DistortionModel::kEquidistant        ? r::PinholeCamera::Distortion::kEquidistant
                 : k->distortion_model == ale::hal::DistortionModel::kRadialTangential ? r::PinholeCamera::Distortion::kRadTan
                                                                                       : r::PinholeCamera::Distortion::kNone;
  c.coeffs = k->distortion;
  Result<ale::geometry::Camera> lens = c.lens();
  if (!lens.ok()) return ale::invalid_argument(path + ": " + lens.status().message());
  return c;
}

// Checkerboard views through `camera`: DIR/view_NNN.png, DIR/calibration.yaml (the true lens),
// DIR/poses.csv (each view's board pose in the camera frame).
int render_checkerboard(const std::string& out, bool overwrite, const r::PinholeCamera& camera,
                        const r::CheckerboardSpec& board, int views, double noise, int supersample,
                        std::uint64_t seed, const std::string& lens_name) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const std::string yaml = (fs::path(out) / "calibration.yaml").string();
  if (fs::exists(yaml, ec) && !overwrite)
    return data_error(ale::invalid_argument(yaml + " already exists (pass --overwrite to replace the views)"));
  if (overwrite) {
    for (fs::directory_iterator it(out, ec), end; !ec && it != end; it.increment(ec)) {
      const std::string name = it->path().filename().string();
      if (name.rfind("view_", 0) == 0 && it->path().extension() == ".png") fs::remove(it->path(), ec);
    }
  }
  fs::create_directories(out, ec);
  if (ec) return data_error(ale::io_error(out + ": cannot create: " + ec.message()));
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<r::BoardPose> poses = r::checkerboard_poses(camera, board, views, seed);
  if (static_cast<int>(poses.size()) < views)
    return data_error(ale::invalid_argument("the whole board fits in the image in only " + std::to_string(poses.size()) +
                                            " of " + std::to_string(views) + " poses: give a smaller --square"));
  const r::CheckerboardRenderer renderer(camera, board, supersample);
  ale::GrayImage image(camera.width, camera.height);
  std::string csv = "#view,file,R_cb (row-major 9),t_cb [m] (3)\n";
  for (int k = 0; k < views; ++k) {
    const r::BoardPose& p = poses[static_cast<std::size_t>(k)];
    Status s = renderer.render(p, noise, ale::mix_seed(seed, static_cast<std::uint64_t>(k) + 1), image.view());
    if (!s.ok()) return data_error(s);
    char name[32];
    std::snprintf(name, sizeof name, "view_%03d.png", k);
    s = ale::io::write_png((fs::path(out) / name).string(), image.view());
    if (!s.ok()) return data_error(s);
    char row[512];
    std::snprintf(row, sizeof row, "%d,%s,%.12g,%.12g,%.12g,%.12g,%.12g,%.12g,%.12g,%.12g,%.12g,%.12g,%.12g,%.12g\n", k, name,
                  p.R_cb(0, 0), p.R_cb(0, 1), p.R_cb(0, 2), p.R_cb(1, 0), p.R_cb(1, 1), p.R_cb(1, 2), p.R_cb(2, 0),
                  p.R_cb(2, 1), p.R_cb(2, 2), p.t_cb.x(), p.t_cb.y(), p.t_cb.z());
    csv += row;
  }
  char comment[200];
  std::snprintf(comment, sizeof comment, "ale-render checkerboard views, lens %s, board %dx%d, square %g m, seed %llu",
                lens_name.c_str(), board.cols, board.rows, board.square_m, static_cast<unsigned long long>(seed));
  Status s = r::write_text_file(yaml, r::sensor_yaml_text(camera, 0.0, r::Rig{}, comment));
  if (s.ok()) s = r::write_text_file((fs::path(out) / "poses.csv").string(), csv);
  if (!s.ok()) return data_error(s);
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("ale-render: %d checkerboard views %dx%d, board %dx%d, square %g m, lens %s, seed %llu (%.2f s)\n", views,
              camera.width, camera.height, board.cols, board.rows, board.square_m, lens_name.c_str(),
              static_cast<unsigned long long>(seed), secs);
  std::printf("wrote %s/view_*.png, calibration.yaml (the true lens), poses.csv\n", out.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::map<std::string, std::string> opt;
  bool overwrite = false;
  const std::vector<std::string> valued = {"--out", "--trajectory", "--frames", "--duration", "--fps", "--light",
                                           "--seed", "--start",
                                           "--width", "--height", "--textures", "--supersample",
                                           "--max-gain", "--read-noise", "--texture-seed", "--lens", "--camera",
                                           "--noise-model", "--full-well", "--fpn-gain", "--fpn-offset",
                                           "--vignetting-power", "--row-noise", "--jpeg-quality",
                                           "--checkerboard", "--square", "--views", "--noise",
                                           "--lanes", "--lane-width", "--lane-length", "--turn-rate", "--room",
                                           "--scene", "--odometry-noise", "--odometry-seed", "--odometry-rate",
                                           "--odometry-clock-offset-ms"};
  // Options that may be given several times, in order.
  const std::vector<std::string> repeated = {"--blackout", "--kidnap"};
  std::map<std::string, std::vector<std::string>> many;
  for (int i = 1; i < argc; ++i) {
    const std::string key = argv[i];
    if (key == "--help" || key == "-h") {
      std::fputs(kUsage, stdout);
      return 0;
    }
    if (key == "--overwrite") {
      overwrite = true;
      continue;
    }
    const bool is_repeated = std::find(repeated.begin(), repeated.end(), key) != repeated.end();
    if (!is_repeated && std::find(valued.begin(), valued.end(), key) == valued.end())
      return usage_error("unknown option '" + key + "'");
    if (i + 1 >= argc) return usage_error(key + " needs a value");
    if (is_repeated) {
      many[key].push_back(argv[++i]);
      continue;
    }
    if (opt.count(key) != 0) return usage_error(key + " given twice");
    opt[key] = argv[++i];
  }
  if (opt.count("--out") == 0) return usage_error("--out DIR is required");

  r::SequenceConfig config;
  long long v = 0;
  double d = 0.0;
  int width = 640;
  int height = 480;
  if (opt.count("--frames")) {
    if (!parse_int(opt["--frames"], 1, 1000000, v)) return usage_error("--frames must be a whole number in 1..1000000");
    config.frames = static_cast<int>(v);
  }
  if (opt.count("--fps")) {
    if (!parse_double(opt["--fps"], 0.1, 1000.0, d)) return usage_error("--fps must be a number in 0.1..1000");
    config.fps = d;
  }
  if (opt.count("--duration")) {
    if (opt.count("--frames")) return usage_error("--duration and --frames both say how long: give one");
    if (!parse_double(opt["--duration"], 0.0, 1e6, d) || std::llround(d * config.fps) < 1 ||
        std::llround(d * config.fps) > 1000000)
      return usage_error("--duration must be seconds giving 1..1000000 frames at the fps");
    config.frames = static_cast<int>(std::llround(d * config.fps));
  }
  const bool frames_given = opt.count("--frames") != 0 || opt.count("--duration") != 0;
  if (opt.count("--start")) {
    if (!parse_double(opt["--start"], 0.0, 1e6, d)) return usage_error("--start must be a number of seconds >= 0");
    config.start_s = d;
  }
  if (opt.count("--seed")) {
    if (!parse_int(opt["--seed"], 0, 9223372036854775807LL, v)) return usage_error("--seed must be a whole number >= 0");
    config.seed = static_cast<std::uint64_t>(v);
  }
  if (opt.count("--width")) {
    if (!parse_int(opt["--width"], 16, 4096, v)) return usage_error("--width must be a whole number in 16..4096");
    width = static_cast<int>(v);
  }
  if (opt.count("--height")) {
    if (!parse_int(opt["--height"], 16, 4096, v)) return usage_error("--height must be a whole number in 16..4096");
    height = static_cast<int>(v);
  }
  const bool checkerboard = opt.count("--checkerboard") != 0;
  if (!checkerboard) {
    for (const char* key : {"--square", "--views", "--noise"})
      if (opt.count(key)) return usage_error(std::string(key) + " is for --checkerboard views");
  }
  int supersample = checkerboard ? 4 : config.supersample;
  if (opt.count("--supersample")) {
    const int most = checkerboard ? 8 : 4;
    if (!parse_int(opt["--supersample"], 1, most, v))
      return usage_error("--supersample must be a whole number in 1.." + std::to_string(most));
    supersample = static_cast<int>(v);
  }
  config.supersample = supersample;
  std::string noise_model = "standard";
  if (const int e = parse_noise_options(opt, noise_model, config.sensor); e != 0) return e;
  if (opt.count("--max-gain")) {
    if (!parse_double(opt["--max-gain"], 1.0, 64.0, d)) return usage_error("--max-gain must be a number in 1..64");
    config.sensor.max_gain = d;
  }
  if (opt.count("--read-noise")) {
    if (!parse_double(opt["--read-noise"], 0.0, 100.0, d)) return usage_error("--read-noise must be a number of electrons in 0..100");
    config.sensor.read_noise_e = d;
  }
  if (opt.count("--light")) {
    Result<r::LightProfile> p = r::parse_light_profile(opt["--light"]);
    if (!p.ok()) return usage_error("--light: " + p.status().message());
    config.light = *p;
  }
  if (opt.count("--lens") && opt.count("--camera")) return usage_error("--lens and --camera both give the lens: give one");
  std::string lens_name = opt.count("--lens") ? opt["--lens"] : "ideal";
  if (opt.count("--camera")) {
    if (opt.count("--width") || opt.count("--height")) return usage_error("--camera gives the image size: no --width/--height");
    Result<r::PinholeCamera> c = camera_from_yaml(opt["--camera"]);
    if (!c.ok()) return usage_error("--camera " + c.status().message());
    config.camera = *c;
    width = c->width;
    height = c->height;
    lens_name = opt["--camera"];
  } else {
    Result<r::PinholeCamera> c = r::PinholeCamera::named(lens_name, width, height);
    if (!c.ok()) return usage_error("--lens: " + c.status().message());
    config.camera = *c;
  }
  if (checkerboard) {
    for (const char* key : {"--trajectory", "--frames", "--duration", "--fps", "--start", "--light", "--textures",
                            "--max-gain", "--read-noise", "--texture-seed", "--lanes", "--lane-width", "--lane-length",
                            "--turn-rate", "--room", "--scene", "--noise-model", "--full-well", "--fpn-gain",
                            "--fpn-offset", "--vignetting-power", "--row-noise", "--jpeg-quality"})
      if (opt.count(key)) return usage_error(std::string(key) + " is for sequences, not --checkerboard views");
    for (const auto& [key, values] : many)
      if (!values.empty()) return usage_error(key + " is for sequences, not --checkerboard views");
    Result<r::CheckerboardSpec> board = r::parse_board(opt["--checkerboard"]);
    if (!board.ok()) return usage_error("--checkerboard: " + board.status().message());
    if (opt.count("--square")) {
      if (!parse_double(opt["--square"], 1e-4, 10.0, d)) return usage_error("--square must be metres in 0.0001..10");
      board->square_m = d;
    }
    long long views = 20;
    if (opt.count("--views") && !parse_int(opt["--views"], 1, 1000, views))
      return usage_error("--views must be a whole number in 1..1000");
    double noise = 1.5;
    if (opt.count("--noise") && !parse_double(opt["--noise"], 0.0, 50.0, noise))
      return usage_error("--noise must be grey levels in 0..50");
    return render_checkerboard(opt["--out"], overwrite, config.camera, *board, static_cast<int>(views), noise,
                               supersample, config.seed, lens_name);
  }
  const bool twin = opt.count("--scene") != 0;
  if (twin && opt["--scene"] != "twin") return usage_error("--scene must be twin (the living room is the default)");
  if (twin && opt.count("--trajectory")) return usage_error("--scene twin drives its own route: no --trajectory");
  if (twin && opt.count("--room")) return usage_error("--scene twin and --room both give the room: give one");
  const std::string trajectory_arg = twin ? "twin" : opt.count("--trajectory") ? opt["--trajectory"] : "loop";
  if (trajectory_arg.empty()) return usage_error("--trajectory needs loop, square, lanes or a file name");
  const bool recorded_path =
      !twin && trajectory_arg != "loop" && trajectory_arg != "square" && trajectory_arg != "lanes";
  r::DriveOptions drive;
  if (opt.count("--turn-rate")) {
    if (trajectory_arg != "square" && trajectory_arg != "lanes" && !twin)
      return usage_error("--turn-rate is for the turns in place of --trajectory square and lanes, and --scene twin");
    if (!parse_double(opt["--turn-rate"], 5.0, 720.0, drive.turn_rate_dps))
      return usage_error("--turn-rate must be degrees per second in 5..720");
  }
  const bool room_given = opt.count("--room") != 0;
  Eigen::Vector3f room_size = Eigen::Vector3f::Zero();
  if (room_given) {
    if (recorded_path)
      return usage_error("--room is for loop, square and lanes: a recorded trajectory gets a hall sized around it");
    std::vector<double> wdh;
    if (!parse_numbers(opt["--room"], 'x', 3, wdh) || wdh[0] < 3.0 || wdh[0] > 30.0 || wdh[1] < 3.0 || wdh[1] > 30.0 ||
        wdh[2] < 2.0 || wdh[2] > 5.0)
      return usage_error("--room must be WxDxH metres, W and D in 3..30, H in 2..5 (e.g. 8x6x2.6), not '" +
                         opt["--room"] + "'");
    room_size = Eigen::Vector3d(wdh[0], wdh[1], wdh[2]).cast<float>();
  }
  r::LaneOptions lanes;
  if (opt.count("--lanes")) {
    if (!parse_int(opt["--lanes"], 2, 12, v)) return usage_error("--lanes must be a whole number in 2..12");
    lanes.lanes = static_cast<int>(v);
  }
  if (opt.count("--lane-width") && !parse_double(opt["--lane-width"], 0.1, 1.0, lanes.width_m))
    return usage_error("--lane-width must be a number of metres in 0.1..1.0");
  if (opt.count("--lane-length") && !parse_double(opt["--lane-length"], 0.5, 20.0, lanes.length_m))
    return usage_error("--lane-length must be a number of metres in 0.5..20 (at most 4 in the living room)");
  if (trajectory_arg != "lanes" && (opt.count("--lanes") || opt.count("--lane-width") || opt.count("--lane-length")))
    return usage_error("--lanes, --lane-width and --lane-length go with --trajectory lanes");
  if (const Status s = r::validate(lanes, !room_given); !s.ok()) return usage_error(s.message());
  for (const std::string& b : many["--blackout"]) {
    std::vector<double> sd;
    if (!parse_numbers(b, ',', 2, sd) || sd[0] < 0.0 || sd[1] <= 0.0)
      return usage_error("--blackout must be START,DURATION in seconds (START >= 0, DURATION > 0), not '" + b + "'");
    config.blackouts.push_back({sd[0], sd[1]});
  }
  for (const std::string& k : many["--kidnap"]) {
    std::vector<double> atg;
    if (!parse_numbers(k, ',', 3, atg) || atg[2] < 0.0 || !(atg[1] < atg[0]) || atg[1] < config.start_s)
      return usage_error("--kidnap must be AT,TO,GAP in seconds with --start <= TO < AT and GAP >= 0, not '" + k + "'");
    config.kidnaps.push_back({atg[0], atg[1], atg[2]});
  }

  r::OdometrySettings odometry;
  if (opt.count("--odometry-noise")) {
    Result<r::OdometryNoise> n = r::parse_odometry_noise(opt["--odometry-noise"]);
    if (!n.ok()) return usage_error("--odometry-noise: " + n.status().message());
    odometry.noise = *n;
  }
  if (opt.count("--odometry-seed")) {
    if (!parse_int(opt["--odometry-seed"], 0, 9223372036854775807LL, v))
      return usage_error("--odometry-seed must be a whole number >= 0");
    odometry.seed = static_cast<std::uint64_t>(v);
  }
  if (opt.count("--odometry-rate") && !parse_double(opt["--odometry-rate"], 15.0, 200.0, odometry.rate_hz))
    return usage_error("--odometry-rate must be samples per second in 15..200, not '" + opt["--odometry-rate"] + "'");
  if (opt.count("--odometry-clock-offset-ms") &&
      !parse_double(opt["--odometry-clock-offset-ms"], -1000.0, 1000.0, odometry.clock_offset_ms))
    return usage_error("--odometry-clock-offset-ms must be milliseconds in -1000..1000, not '" +
                       opt["--odometry-clock-offset-ms"] + "'");
  if (recorded_path) {
    for (const char* key : {"--odometry-noise", "--odometry-seed", "--odometry-rate", "--odometry-clock-offset-ms"})
      if (opt.count(key))
        return usage_error(std::string(key) + " is for the sweeper's routes: a recorded flight gets no wheel odometry");
  }

  const auto t_start = std::chrono::steady_clock::now();
  r::SceneOptions scene_options;
  if (opt.count("--texture-seed")) {
    if (opt.count("--textures")) return usage_error("--texture-seed is for the procedural textures, not with --textures");
    if (!parse_int(opt["--texture-seed"], 0, 4294967295LL, v)) return usage_error("--texture-seed must be a whole number in 0..4294967295");
    scene_options.seed = static_cast<std::uint32_t>(v);
  }
  if (opt.count("--textures")) {
    const Status s = load_photos(opt["--textures"], scene_options.photos);
    if (!s.ok()) return data_error(s);
  }

  // The sweeper's trajectories start at a fixed date; recorded ones keep their own timestamps.
  std::int64_t start_ns = 1700000000000000000LL;
  r::Trajectory trajectory;
  r::Rig rig = r::sweeper_rig(12.0);
  Result<r::Scene> scene = ale::invalid_argument("no scene");
  std::string fit_note;
  if (!recorded_path) {
    // The routes need only the room's size; a hall is then furnished around the route.
    r::Scene sized;
    if (room_given) sized.size = room_size;
    if (twin) scene = r::build_twin_scene(scene_options);
    else if (room_given) scene = sized;
    else scene = r::build_default_scene(scene_options);
    if (!scene.ok()) return data_error(scene.status());
    const double duration = config.start_s + (config.frames - 1) / config.fps;
    if (twin) trajectory = r::make_twin_route(*scene, drive, duration);
    else if (trajectory_arg == "loop") trajectory = r::make_loop(*scene, drive, duration);
    else if (trajectory_arg == "square") trajectory = r::make_square(*scene, drive, duration);
    else trajectory = r::make_lanes(*scene, drive, lanes, duration);
    if (room_given) {
      const std::vector<Eigen::Vector3f> path = r::path_points(trajectory, rig, 0.0, duration);
      Eigen::Vector3f lo = path.front(), hi = path.front();
      for (const Eigen::Vector3f& p : path) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
      constexpr float kWallClearance = 0.3f;
      if (lo.x() < kWallClearance || lo.y() < kWallClearance || hi.x() > room_size.x() - kWallClearance ||
          hi.y() > room_size.y() - kWallClearance) {
        char buf[200];
        std::snprintf(buf, sizeof buf, "the %s route spans %.2f x %.2f m: it does not fit in the %g x %g m room "
                      "with %.1f m to the walls (--room)", trajectory_arg.c_str(), hi.x() - lo.x(), hi.y() - lo.y(),
                      room_size.x(), room_size.y(), kWallClearance);
        return usage_error(buf);
      }
      scene = r::build_hall_scene(scene_options, room_size, path, kFurnitureClearance);
      if (!scene.ok()) return data_error(scene.status());
      char buf[160];
      std::snprintf(buf, sizeof buf, "room: %g x %g x %g m hall, %zu boxes\n", room_size.x(), room_size.y(),
                    room_size.z(), scene->boxes.size());
      fit_note = buf;
    }
  } else {
    // A file's problems are the caller's: usage errors (exit 2), naming the file.
    const std::string& file = trajectory_arg;
    Result<std::vector<r::TimedPose>> recorded = load_recorded(file, start_ns);
    if (!recorded.ok()) return usage_error("--trajectory " + recorded.status().message());
    if (recorded->size() < 2) return usage_error("--trajectory " + file + ": fewer than 2 poses");
    rig = r::euroc_cam0_rig();
    const double length = recorded->back().t_s - recorded->front().t_s;
    if (config.start_s >= length)
      return usage_error("--start " + std::to_string(config.start_s) + " s is past the end of " + file + " (" +
                         std::to_string(length) + " s)");
    const int available = static_cast<int>(std::floor((length - config.start_s) * config.fps + 1e-9)) + 1;
    if (!frames_given) config.frames = available;
    if (config.frames > available)
      return usage_error(file + " lasts " + std::to_string(length) + " s: from " + std::to_string(config.start_s) +
                         " s at most " + std::to_string(available) + " frames at this fps");
    const double end_s = config.start_s + (config.frames - 1) / config.fps;
    r::RoomPlacement room;
    Result<r::Trajectory> placed = r::place_in_room(*recorded, rig, config.start_s, end_s, r::RoomMargins{}, &room);
    if (!placed.ok()) return usage_error("--trajectory " + file + ": " + placed.status().message());
    trajectory = std::move(*placed);
    const std::vector<Eigen::Vector3f> path = r::path_points(trajectory, rig, config.start_s, end_s);
    scene = r::build_hall_scene(scene_options, room.size.cast<float>(), path, kFurnitureClearance);
    if (!scene.ok()) return data_error(scene.status());
    int in_furniture = 0;
    for (const Eigen::Vector3f& p : path) in_furniture += scene->inside_box(p, 0.02f) ? 1 : 0;
    char buf[320];
    std::snprintf(buf, sizeof buf,
                  "room: %.2f x %.2f x %.2f m around the path's box (%.2f %.2f %.2f) .. (%.2f %.2f %.2f), "
                  "moved by (%.3f %.3f %.3f); %zu boxes; %d of %zu path points inside furniture\n",
                  room.size.x(), room.size.y(), room.size.z(), room.path_lo.x(), room.path_lo.y(), room.path_lo.z(),
                  room.path_hi.x(), room.path_hi.y(), room.path_hi.z(), room.offset.x(), room.offset.y(),
                  room.offset.z(), scene->boxes.size(), in_furniture, path.size());
    fit_note = buf;
  }
  const double duration = config.start_s + (config.frames - 1) / config.fps;

  Result<r::SequenceRenderer> seq = r::SequenceRenderer::create(*scene, trajectory, rig, config);
  if (!seq.ok()) return data_error(seq.status());
  Result<r::EurocWriter> writer = r::EurocWriter::create(opt["--out"], overwrite);
  if (!writer.ok()) return data_error(writer.status());
  char comment[256];
  std::snprintf(comment, sizeof comment, "ale-render camera, trajectory %s, light %s, seed %llu, noise %s",
                trajectory_arg.c_str(), r::to_string(config.light), static_cast<unsigned long long>(config.seed),
                noise_model.c_str());
  const std::string noise_notes = r::describe_noise(noise_model, config.sensor);
  Status s = writer->write_sensor_yaml(config.camera, config.fps, rig, comment, noise_notes);
  if (!s.ok()) return data_error(s);

  const auto t_scene = std::chrono::steady_clock::now();
  ale::GrayImage frame(width, height);
  double grey_min = 255.0, grey_max = 0.0, grey_sum = 0.0;
  std::vector<r::FrameTime> frame_times;
  for (int k = 0; k < config.frames; ++k) {
    r::FrameRecord rec;
    s = seq->render_next(frame.view(), rec);
    if (!s.ok()) return data_error(s);
    const std::int64_t ts =
        start_ns + std::llround(config.start_s * 1e9) + std::llround(k * 1e9 / config.fps) + rec.gap_ns;
    // Central differences, one-sided at the ends of the trajectory.
    const double t_lo = std::max(0.0, rec.t_s - 0.005);
    const double t_hi = std::min(trajectory.duration_s(), rec.t_s + 0.005);
    const Eigen::Vector3d vel = t_hi > t_lo ? Eigen::Vector3d((trajectory.at(t_hi).p_wb - trajectory.at(t_lo).p_wb) / (t_hi - t_lo))
                                            : Eigen::Vector3d::Zero();
    s = writer->add_frame(ts, frame.view(), rec, vel, rec.blackout ? "blackout" : r::to_string(config.light));
    if (!s.ok()) return data_error(s);
    frame_times.push_back({ts, rec.t_s});
    grey_min = std::min(grey_min, rec.mean_grey);
    grey_max = std::max(grey_max, rec.mean_grey);
    grey_sum += rec.mean_grey;
  }
  s = writer->finish();
  if (!s.ok()) return data_error(s);
  std::string odometry_note;
  if (!recorded_path) {
    const Result<std::string> note =
        r::write_sweeper_odometry(*writer, trajectory, rig, r::sweeper_T_BC(rig, drive), frame_times, odometry, trajectory_arg);
    if (!note.ok()) return data_error(note.status());
    odometry_note = *note;
  }
  const auto t_end = std::chrono::steady_clock::now();
  const double scene_s = std::chrono::duration<double>(t_scene - t_start).count();
  const double render_s = std::chrono::duration<double>(t_end - t_scene).count();
  std::printf("ale-render: %d frames %dx%d at %g fps (to %.2f s), trajectory %s, light %s, seed %llu\n", config.frames,
              width, height, config.fps, duration, trajectory_arg.c_str(), r::to_string(config.light),
              static_cast<unsigned long long>(config.seed));
  std::fputs(fit_note.c_str(), stdout);
  std::printf("sensor: %s\n", one_line(noise_notes).c_str());
  if (opt.count("--turn-rate")) std::printf("turns in place at %g deg/s\n", drive.turn_rate_dps);
  for (const r::Blackout& b : config.blackouts)
    std::printf("blackout: all light off from %.3f s to %.3f s after the first frame\n", b.start_s,
                b.start_s + b.duration_s);
  for (const r::Kidnap& k : config.kidnaps)
    std::printf("kidnap: at %.3f s on the trajectory to its pose at %.3f s, %.3f s without frames\n", k.at_s, k.to_s,
                k.gap_s);
  std::printf("mean grey: min %.1f, mean %.1f, max %.1f\n", grey_min, grey_sum / config.frames, grey_max);
  std::fputs(odometry_note.c_str(), stdout);
  std::printf("time: scene %.2f s, %.1f ms per frame (render + PNG)\n", scene_s, 1000.0 * render_s / config.frames);
  std::printf("wrote %s/mav0 (cam0, state_groundtruth_estimate0%s), groundtruth.txt, lighting.csv\n",
              writer->out_dir().c_str(), odometry_note.rfind("odometry:", 0) == 0 ? ", odometry0" : "");
  return 0;
}
