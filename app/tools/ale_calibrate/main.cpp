// ale-calibrate: a camera's calibration (intrinsics and distortion) from checkerboard views,
// written as the sensor.yaml ale-slamd reads (docs/calibration.md).
//
//   ale-calibrate --board COLSxROWS --square METRES [--model pinhole|fisheye] --out FILE.yaml
//                 [--report FILE.html] [--extrinsics FILE.yaml] [--min-views N] [--max-blur PX]
//                 [--duplicate-px PX] IMAGE_OR_FOLDER...
//
// Exit status: 0 ok, 1 bad data (an unreadable image, mixed image sizes, no board found, too few
// good views, a failed fit or write), 2 bad usage.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "app/tools/lib/calib/calibration.h"
#include "app/tools/lib/calib/report.h"
#include "app/tools/lib/eval/text.h"
#include "app/tools/lib/render/sensor_yaml.h"
#include "core/io/image_io.h"
#include "hal/replay/dataset.h"

namespace {

namespace fs = std::filesystem;
namespace c = ale::calib;
namespace r = ale::render;
using ale::Result;
using ale::Status;

constexpr int kExitData = 1;
constexpr int kExitUsage = 2;
// A view whose corners sit further than this many times the median view's RMS from the fit is
// a misdetection or a moving board; it is dropped and the lens fitted again.
constexpr double kOutlierFactor = 3.0;
constexpr double kOutlierFloorPx = 0.5;

constexpr const char* kUsage =
    "usage: ale-calibrate --board COLSxROWS --square METRES --out FILE.yaml [options] IMAGE_OR_FOLDER...\n"
    "  --board COLSxROWS  inner corners along a row and a column of the checkerboard (e.g. 9x6)\n"
    "  --square METRES    side of one square\n"
    "  --model M          pinhole (radial-tangential k1 k2 p1 p2, default) or fisheye (equidistant\n"
    "                     k1..k4)\n"
    "  --out FILE.yaml    the calibration, in the sensor.yaml schema ale-slamd reads\n"
    "  --report FILE      the HTML report (default: FILE.yaml's name with .html)\n"
    "  --extrinsics FILE  a sensor.yaml whose T_BS (camera to body) and rate_hz are kept (default:\n"
    "                     a recording's own sensor.yaml, else identity)\n"
    "  --min-views N      fewest good views to fit, 4..1000 (default 8)\n"
    "  --max-blur PX      edges wider than this (10-90 % rise, pixels) reject a view (default 5)\n"
    "  --duplicate-px PX  a view whose corners are on average closer than this to an earlier\n"
    "                     view's is a duplicate (default 1 % of the image diagonal)\n"
    "inputs: PNG or JPEG images, folders of them, or recordings of the daemon's recorder (EuRoC\n"
    "layout: a folder with mav0/cam0/data/, or the recorder's folder of such sequences)\n";

int usage_error(const std::string& message) {
  std::fprintf(stderr, "ale-calibrate: %s\n%s", message.c_str(), kUsage);
  return kExitUsage;
}

int data_error(const std::string& message) {
  std::fprintf(stderr, "ale-calibrate: %s\n", message.c_str());
  return kExitData;
}

// A finite number in [lo, hi].
bool parse_in_range(const std::string& text, double lo, double hi, double& out) {
  double v = 0.0;
  if (!ale::eval::parse_double(text, &v) || !std::isfinite(v) || v < lo || v > hi) return false;
  out = v;
  return true;
}

bool is_image_name(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return ext == ".png" || ext == ".jpg" || ext == ".jpeg";
}

bool is_recording(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(p / "mav0" / "cam0" / "data", ec) || fs::is_directory(p / "cam0" / "data", ec) ||
         (fs::is_directory(p / "data", ec) && fs::is_regular_file(p / "data.csv", ec));
}

struct Inputs {
  std::vector<std::string> images;
  std::optional<ale::hal::CameraCalibration> recording_lens;  // the first recording's sensor.yaml
};

// A recording's frames: the images in its cam0/data folder, in time order (their names are
// timestamps of equal length); its sensor.yaml, when it has one, gives T_BS and rate_hz.
Status add_recording(const fs::path& folder, Inputs& in) {
  std::error_code ec;
  fs::path cam0 = folder;
  if (fs::is_directory(folder / "mav0" / "cam0", ec)) cam0 = folder / "mav0" / "cam0";
  else if (fs::is_directory(folder / "cam0", ec)) cam0 = folder / "cam0";
  std::vector<std::string> frames;
  for (fs::directory_iterator it(cam0 / "data", ec), end; !ec && it != end; it.increment(ec))
    if (it->is_regular_file(ec) && is_image_name(it->path())) frames.push_back(it->path().string());
  if (ec) return ale::io_error((cam0 / "data").string() + ": cannot list: " + ec.message());
  if (frames.empty()) return ale::not_found((cam0 / "data").string() + ": a recording without frames");
  std::sort(frames.begin(), frames.end(), [](const std::string& a, const std::string& b) {
    return a.size() != b.size() ? a.size() < b.size() : a < b;
  });
  in.images.insert(in.images.end(), frames.begin(), frames.end());
  if (!in.recording_lens && fs::is_regular_file(cam0 / "sensor.yaml", ec)) {
    Result<ale::hal::CameraCalibration> lens = ale::replay::read_euroc_sensor_yaml((cam0 / "sensor.yaml").string());
    if (!lens.ok()) return lens.status();
    in.recording_lens = *lens;
  }
  return {};
}

// Every image the arguments name, in order (a folder's sorted by name).
Status collect_inputs(const std::vector<std::string>& args, Inputs& in) {
  for (const std::string& arg : args) {
    std::error_code ec;
    const fs::path p(arg);
    if (!fs::exists(p, ec)) return ale::not_found(arg + ": no such file or folder");
    if (!fs::is_directory(p, ec)) {
      in.images.push_back(arg);
      continue;
    }
    if (is_recording(p)) {
      ALE_RETURN_IF_ERROR(add_recording(p, in));
      continue;
    }
    std::vector<std::string> files, sequences;
    for (fs::directory_iterator it(p, ec), end; !ec && it != end; it.increment(ec)) {
      if (it->is_regular_file(ec) && is_image_name(it->path())) files.push_back(it->path().string());
      if (it->is_directory(ec) && is_recording(it->path())) sequences.push_back(it->path().string());
    }
    if (ec) return ale::io_error(arg + ": cannot list: " + ec.message());
    std::sort(files.begin(), files.end());
    std::sort(sequences.begin(), sequences.end());
    if (files.empty() && sequences.empty())
      return ale::not_found(arg + ": no .png or .jpg images and no recordings (mav0/cam0/data.csv) in the folder");
    in.images.insert(in.images.end(), files.begin(), files.end());
    for (const std::string& s : sequences) ALE_RETURN_IF_ERROR(add_recording(fs::path(s), in));
  }
  return {};
}

std::string fmt(const char* format, double a, double b = 0.0, double c = 0.0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, format, a, b, c);
  return buf;
}

std::string file_name(const std::string& path) { return fs::path(path).filename().string(); }

r::Rig rig_of(const ale::hal::CameraCalibration& k) {
  r::Rig rig;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) rig.R_bc(i, j) = k.T_BS[static_cast<std::size_t>(4 * i + j)];
    rig.t_bc(i) = k.T_BS[static_cast<std::size_t>(4 * i + 3)];
  }
  return rig;
}

}  // namespace

int main(int argc, char** argv) {
  std::map<std::string, std::string> opt;
  std::vector<std::string> inputs;
  const std::vector<std::string> valued = {"--board", "--square", "--model", "--out", "--report", "--extrinsics",
                                           "--min-views", "--max-blur", "--duplicate-px"};
  for (int i = 1; i < argc; ++i) {
    const std::string key = argv[i];
    if (key == "--help" || key == "-h") {
      std::fputs(kUsage, stdout);
      return 0;
    }
    if (key.rfind("--", 0) != 0) {
      inputs.push_back(key);
      continue;
    }
    if (std::find(valued.begin(), valued.end(), key) == valued.end()) return usage_error("unknown option '" + key + "'");
    if (i + 1 >= argc) return usage_error(key + " needs a value");
    if (opt.count(key) != 0) return usage_error(key + " given twice");
    opt[key] = argv[++i];
  }
  for (const char* key : {"--board", "--square", "--out"})
    if (opt.count(key) == 0) return usage_error(std::string(key) + " is required");
  if (inputs.empty()) return usage_error("no images or folders given");
  Result<r::CheckerboardSpec> board = r::parse_board(opt["--board"]);
  if (!board.ok()) return usage_error("--board: " + board.status().message());
  double d = 0.0;
  if (!parse_in_range(opt["--square"], 1e-4, 10.0, d)) return usage_error("--square must be metres in 0.0001..10");
  board->square_m = d;
  const std::string model_name = opt.count("--model") ? opt["--model"] : "pinhole";
  if (model_name != "pinhole" && model_name != "fisheye") return usage_error("--model must be pinhole or fisheye");
  const c::LensModel model = model_name == "fisheye" ? c::LensModel::kFisheye : c::LensModel::kPinholeRadTan;
  int min_views = 8;
  if (opt.count("--min-views")) {
    if (!parse_in_range(opt["--min-views"], 4, 1000, d) || d != std::floor(d))
      return usage_error("--min-views must be a whole number in 4..1000");
    min_views = static_cast<int>(d);
  }
  double max_blur = 5.0;
  if (opt.count("--max-blur") && !parse_in_range(opt["--max-blur"], 0.5, 100.0, max_blur))
    return usage_error("--max-blur must be pixels in 0.5..100");
  double duplicate_px = -1.0;
  if (opt.count("--duplicate-px") && !parse_in_range(opt["--duplicate-px"], 0.0, 1000.0, duplicate_px))
    return usage_error("--duplicate-px must be pixels in 0..1000");
  const std::string out = opt["--out"];
  const std::string report = opt.count("--report") ? opt["--report"] : fs::path(out).replace_extension(".html").string();
  std::optional<ale::hal::CameraCalibration> extrinsics;
  if (opt.count("--extrinsics")) {
    Result<ale::hal::CameraCalibration> e = ale::replay::read_euroc_sensor_yaml(opt["--extrinsics"]);
    if (!e.ok()) return usage_error("--extrinsics " + e.status().message());
    extrinsics = *e;
  }

  Inputs in;
  if (Status s = collect_inputs(inputs, in); !s.ok()) return data_error(s.message());
  if (!extrinsics && in.recording_lens) extrinsics = in.recording_lens;

  // Detection, then the views that are blurred or repeat an earlier one are set aside.
  int width = 0, height = 0;
  std::string first_image;
  std::vector<std::string> names;
  std::vector<std::vector<Eigen::Vector2d>> views;
  std::vector<double> blurs;
  std::vector<std::pair<std::string, std::string>> rejected;
  int boards_found = 0;
  ale::GrayImage image;
  for (const std::string& path : in.images) {
    Status s = ale::io::read_gray(path, image);
    if (!s.ok()) return data_error("unreadable image: " + s.message());
    if (width == 0) {
      width = image.width;
      height = image.height;
      first_image = path;
      if (duplicate_px < 0.0) duplicate_px = 0.01 * std::hypot(width, height);
    } else if (image.width != width || image.height != height) {
      return data_error("mixed image sizes: " + path + " is " + std::to_string(image.width) + "x" +
                        std::to_string(image.height) + ", " + first_image + " " + std::to_string(width) + "x" +
                        std::to_string(height) + " (calibrate one camera mode at a time)");
    }
    const c::Detection det = c::detect_board(image.view(), *board);
    if (!det.found) {
      rejected.emplace_back(path, "no board: not all " + std::to_string(board->cols) + "x" + std::to_string(board->rows) +
                                      " inner corners found");
      continue;
    }
    ++boards_found;
    if (det.blur_px > max_blur) {
      rejected.emplace_back(path, fmt("blurred: edges %.1f px wide (10-90 %%), over --max-blur %.1f", det.blur_px, max_blur));
      continue;
    }
    std::size_t twin = views.size();
    double closest = 1e9;
    for (std::size_t v = 0; v < views.size(); ++v) {
      const double dist = c::mean_corner_distance(det.corners, views[v]);
      if (dist < closest) {
        closest = dist;
        twin = v;
      }
    }
    if (twin < views.size() && closest < duplicate_px) {
      rejected.emplace_back(path, "duplicate of " + file_name(names[twin]) +
                                      fmt(": corners %.1f px apart on average (under %.1f)", closest, duplicate_px));
      continue;
    }
    names.push_back(path);
    views.push_back(det.corners);
    blurs.push_back(det.blur_px);
  }
  const std::string needed = std::to_string(board->cols) + "x" + std::to_string(board->rows);
  if (boards_found == 0)
    return data_error("no board found: none of the " + std::to_string(in.images.size()) + " images shows all " + needed +
                      " inner corners of the checkerboard (is --board the count of inner corners, COLSxROWS?)");
  const auto too_few = [&](std::size_t good) {
    std::string why;
    std::map<std::string, int> counts;
    // The reason's first words: "no board", "blurred", "duplicate", "poor fit".
    for (const auto& rj : rejected) ++counts[rj.second.substr(0, std::min(rj.second.find(':'), rj.second.find(" of ")))];
    for (const auto& [reason, n] : counts) why += (why.empty() ? "" : ", ") + std::to_string(n) + " " + reason;
    return data_error("too few good views: " + std::to_string(good) + " of " + std::to_string(in.images.size()) +
                      " images, at least " + std::to_string(min_views) + " needed (rejected: " + why +
                      "); show the board in more places and tilts");
  };
  if (static_cast<int>(views.size()) < min_views) return too_few(views.size());

  Result<c::Calibration> cal = c::calibrate(views, *board, model, width, height);
  if (!cal.ok()) return data_error(cal.status().message());
  // The corners refined again with this lens (the edges it bends are straight for the corner
  // model then), and the lens fitted to them.
  const auto image_of = [&](std::size_t v, ale::GrayImage& view_image) { return ale::io::read_gray(names[v], view_image); };
  cal = c::refit_with_lens(image_of, views, *board, model, width, height, *cal);
  if (!cal.ok()) return data_error(cal.status().message());
  // One round of outlier views: dropped and the lens fitted again.
  std::vector<double> sorted = cal->view_rms_px;
  std::sort(sorted.begin(), sorted.end());
  const double limit = std::max(kOutlierFloorPx, kOutlierFactor * sorted[sorted.size() / 2]);
  std::vector<std::string> kept_names;
  std::vector<std::vector<Eigen::Vector2d>> kept;
  std::vector<double> kept_blurs;
  for (std::size_t v = 0; v < views.size(); ++v) {
    if (cal->view_rms_px[v] > limit) {
      rejected.emplace_back(names[v], fmt("poor fit: RMS %.2f px, over %.2f (3x the median view's)", cal->view_rms_px[v], limit));
    } else {
      kept_names.push_back(names[v]);
      kept.push_back(views[v]);
      kept_blurs.push_back(blurs[v]);
    }
  }
  if (kept.size() != views.size()) {
    if (static_cast<int>(kept.size()) < min_views) return too_few(kept.size());
    names = kept_names;
    views = kept;
    blurs = kept_blurs;
    cal = c::calibrate(views, *board, model, width, height);
    if (!cal.ok()) return data_error(cal.status().message());
  }

  const c::Coverage coverage = c::corner_coverage(views, width, height);
  const std::array<const char*, 8> pnames = c::parameter_names(model);
  const double values[8] = {cal->camera.fx, cal->camera.fy, cal->camera.cx, cal->camera.cy,
                            cal->camera.coeffs[0], cal->camera.coeffs[1], cal->camera.coeffs[2], cal->camera.coeffs[3]};
  std::string params;
  for (std::size_t k = 0; k < 8; ++k)
    params += pnames[k] + fmt(k < 4 ? " %.3f +- %.3f px\n" : " %.6f +- %.6f\n", values[k], cal->stddev[k]);
  const std::string summary =
      std::to_string(views.size()) + " views used of " + std::to_string(in.images.size()) + " images (" +
      std::to_string(rejected.size()) + " rejected), board " + needed + fmt(" squares %g m", board->square_m) +
      ", model " + model_name + ", " + std::to_string(width) + "x" + std::to_string(height) + "\n" + fmt("rms %.3f px over ", cal->rms_px) +
      std::to_string(cal->corners) + fmt(" corners; per view %.3f .. %.3f px\n", *std::min_element(cal->view_rms_px.begin(), cal->view_rms_px.end()),
                                    *std::max_element(cal->view_rms_px.begin(), cal->view_rms_px.end())) +
      fmt("coverage %.0f %% of the image's cells (", 100.0 * coverage.share) + std::to_string(coverage.cols) + "x" +
      std::to_string(coverage.rows) + " grid)\n";
  std::fputs(("ale-calibrate: " + summary).c_str(), stdout);
  for (const auto& [path, why] : rejected) std::printf("rejected %s: %s\n", path.c_str(), why.c_str());
  for (std::size_t v = 0; v < views.size(); ++v) std::printf("view %s: rms %.3f px, edges %.1f px wide\n", file_name(names[v]).c_str(), cal->view_rms_px[v], blurs[v]);
  std::fputs(params.c_str(), stdout);
  if (coverage.share < 0.6)
    std::printf("warning: the corners miss %.0f %% of the image: the distortion there is extrapolated; add views "
                "with the board near the image's edges and corners\n", 100.0 * (1.0 - coverage.share));

  const r::Rig rig = extrinsics ? rig_of(*extrinsics) : r::Rig{};
  const double rate = extrinsics ? extrinsics->rate_hz : 0.0;
  std::string notes = "Calibrated by ale-calibrate: " + summary;
  notes += extrinsics ? "T_BS (camera to body) and rate_hz from " + (opt.count("--extrinsics") ? opt["--extrinsics"] : std::string("the recording's sensor.yaml")) + "\n"
                      : "T_BS is the identity: replace it with the measured camera-to-body transform (docs/calibration.md)\n";
  Status s = r::write_text_file(out, r::sensor_yaml_text(cal->camera, rate, rig, "ale-calibrate, " + model_name + " model", notes));
  if (!s.ok()) return data_error(s.message());
  // The file must read back as the daemon reads it.
  Result<ale::hal::CameraCalibration> back = ale::replay::read_euroc_sensor_yaml(out);
  if (!back.ok()) return data_error("the written calibration does not read back: " + back.status().message());

  c::ReportInput rep;
  rep.title = "Camera calibration: " + file_name(out);
  rep.figures = {{"views used", std::to_string(views.size()) + " of " + std::to_string(in.images.size()) + " images"},
                 {"board", needed + fmt(" inner corners, squares %g m", board->square_m)},
                 {"model", model_name == "fisheye" ? "fisheye (equidistant)" : "pinhole, radial-tangential"},
                 {"image", std::to_string(width) + "x" + std::to_string(height)},
                 {"rms reprojection error", fmt("%.3f px over ", cal->rms_px) + std::to_string(cal->corners) + " corners"},
                 {"per view", fmt("%.3f .. %.3f px", *std::min_element(cal->view_rms_px.begin(), cal->view_rms_px.end()),
                                  *std::max_element(cal->view_rms_px.begin(), cal->view_rms_px.end()))},
                 {"coverage", fmt("%.0f %% of the image's cells", 100.0 * coverage.share)},
                 {"calibration file", out}};
  rep.model = model;
  rep.calibration = &*cal;
  for (const std::string& n : names) rep.view_names.push_back(file_name(n));
  rep.views = views;
  rep.rejected = rejected;
  rep.coverage = coverage;
  s = c::write_report(report, rep);
  if (!s.ok()) return data_error(s.message());
  std::printf("wrote %s and %s\n", out.c_str(), report.c_str());
  return 0;
}
