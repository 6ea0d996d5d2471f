// The recorded-dataset readers (hal/replay/dataset.h), which read files by path: the fuzz input
// replaces one file of a small valid EuRoC + TUM tree built once in a temporary folder, and the
// reader of that file runs. The input's first byte chooses the file (its value modulo 6, so the
// seeds start with a digit '0'..'5'); the rest is the file's text:
//   0 mav0/cam0/data.csv (EuRoC frame list)       -> open_dataset()
//   1 mav0/cam0/sensor.yaml (camera calibration)  -> read_euroc_sensor_yaml()
//   2 mav0/odometry0/data.csv (wheel odometry)    -> read_odometry_folder()
//   3 mav0/odometry0/sensor.yaml (rate_hz, T_BC)  -> read_odometry_folder()
//   4 mav0/state_groundtruth_estimate0/data.csv   -> read_euroc_groundtruth()
//   5 rgb.txt (TUM frame list)                    -> open_dataset()
// What a reader accepts must hold what dataset.h promises: frames and rows in strictly increasing
// time, a calibration of positive focal lengths and a size in 1..16384.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/io/image_io.h"
#include "hal/replay/dataset.h"

namespace {

namespace fs = std::filesystem;

struct TreeFile {
  const char* path;  // relative to the tree's root
  const char* text;  // its valid content
};

constexpr const char* kCameraYaml =
    "sensor_type: camera\nrate_hz: 20\nresolution: [4, 3]\ncamera_model: pinhole\n"
    "intrinsics: [458.654, 457.296, 367.215, 248.375]\ndistortion_model: radial-tangential\n"
    "distortion_coefficients: [-0.28, 0.07, 0.0002, 1.76e-05]\n"
    "T_BS:\n  cols: 4\n  rows: 4\n  data: [1, 0, 0, 0,\n         0, 1, 0, 0,\n         0, 0, 1, 0,\n         0, 0, 0, 1]\n";

const TreeFile kFiles[] = {
    {"euroc/mav0/cam0/data.csv", "#timestamp [ns],filename\n1403715273262142976,1.png\n1403715273312143104,1.png\n"},
    {"euroc/mav0/cam0/sensor.yaml", kCameraYaml},
    {"euroc/mav0/odometry0/data.csv",
     "#timestamp [ns],x [m],y [m],theta [rad],gyro_z [rad/s]\n1000,0,0,0,0.1\n2000,0.01,0,0.001,nan\n"},
    {"euroc/mav0/odometry0/sensor.yaml",
     "rate_hz: 50\nT_BC:\n  rows: 4\n  cols: 4\n  data: [0, 0, 1, 0.1, -1, 0, 0, 0, 0, -1, 0, 0.08, 0, 0, 0, 1]\n"},
    {"euroc/mav0/state_groundtruth_estimate0/data.csv",
     "#timestamp,p_x,p_y,p_z,q_w,q_x,q_y,q_z\n1403715273262142976,1,2,3,1,0,0,0\n"},
    {"tum/rgb.txt", "# timestamp filename\n1311868164.363181 rgb/1.png\n1311868164.399454 rgb/1.png\n"},
};
constexpr int kKinds = sizeof kFiles / sizeof kFiles[0];

std::string root;

void write_text(const std::string& path, const char* data, std::size_t size) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(data, static_cast<std::streamsize>(size));
  if (!out) std::abort();
}

void write_text(const std::string& path, const std::string& text) { write_text(path, text.data(), text.size()); }

void remove_tree() { fs::remove_all(root); }

void check(bool ok) {
  if (!ok) std::abort();
}

template <class T>
bool increasing(const std::vector<T>& v) {
  for (std::size_t i = 1; i < v.size(); ++i)
    if (v[i].timestamp_ns <= v[i - 1].timestamp_ns) return false;
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  char dir[] = "/tmp/ale-fuzz-dataset-XXXXXX";
  if (::mkdtemp(dir) == nullptr) std::abort();
  root = dir;
  std::atexit(remove_tree);
  for (const char* d : {"euroc/mav0/cam0/data", "euroc/mav0/odometry0", "euroc/mav0/state_groundtruth_estimate0", "tum/rgb"})
    fs::create_directories(root + "/" + d);
  for (const TreeFile& f : kFiles) write_text(root + "/" + f.path, f.text);
  // One 4x3 frame, listed twice by each frame list (a reader checks that frames exist and probes
  // the first).
  ale::GrayImage frame(4, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 4; ++x) frame.view().row(y)[x] = static_cast<std::uint8_t>(40 * x + y);
  for (const char* png : {"euroc/mav0/cam0/data/1.png", "tum/rgb/1.png"})
    if (!ale::io::write_png(root + "/" + png, frame.view()).ok()) std::abort();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace ale::replay;
  if (size < 1) return 0;
  const int kind = data[0] % kKinds;
  const std::string file = root + "/" + kFiles[kind].path;
  write_text(file, reinterpret_cast<const char*>(data + 1), size - 1);
  const std::string euroc = root + "/euroc";
  switch (kind) {
    case 0:
    case 5: {
      const ale::Result<Dataset> ds = open_dataset(kind == 0 ? euroc : root + "/tum", DatasetOptions{false});
      if (ds.ok()) check(!ds->frames.empty() && increasing(ds->frames) && ds->width == 4 && ds->height == 3);
      break;
    }
    case 1: {
      const ale::Result<ale::hal::CameraCalibration> c = read_euroc_sensor_yaml(file);
      if (c.ok())
        check(c->fx > 0 && c->fy > 0 && c->width >= 1 && c->width <= 16384 && c->height >= 1 && c->height <= 16384);
      break;
    }
    case 2:
    case 3: {
      const ale::Result<OdometryTrack> t = read_odometry_folder(euroc + "/mav0/odometry0");
      if (t.ok()) check(!t->rows.empty() && increasing(t->rows) && t->rate_hz >= 0);
      break;
    }
    case 4: {
      const ale::Result<std::vector<GroundTruthState>> g =
          read_euroc_groundtruth(euroc + "/mav0/state_groundtruth_estimate0/data.csv");
      if (g.ok()) check(!g->empty() && increasing(*g));
      break;
    }
  }
  write_text(file, kFiles[kind].text);  // the next input finds the tree valid again
  return 0;
}
