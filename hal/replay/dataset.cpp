#include "hal/replay/dataset.h"

#include <sys/stat.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <system_error>

#include "core/io/image_io.h"

namespace ale::replay {

namespace fs = std::filesystem;

const char* to_string(DatasetFormat format) {
  switch (format) {
    case DatasetFormat::kEuroc:
      return "EuRoC";
    case DatasetFormat::kTum:
      return "TUM";
  }
  return "?";
}

namespace {

bool is_file(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

bool is_dir(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

std::string join(const std::string& a, const std::string& b) {
  if (a.empty() || a.back() == '/') return a + b;
  return a + "/" + b;
}

std::string_view trim(std::string_view s) {
  const auto is_space = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
  while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
  return s;
}

std::string at_line(const std::string& file, int line) { return file + ":" + std::to_string(line) + ": "; }

// The lines of a text file, without their end-of-line characters (\n or \r\n).
Status read_lines(const std::string& path, std::vector<std::string>& lines) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return is_file(path) ? io_error(path + ": cannot open") : not_found(path + ": no such file");
  lines.clear();
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    lines.push_back(std::move(line));
  }
  if (in.bad()) return io_error(path + ": read failed");
  return {};
}

std::vector<std::string_view> split(std::string_view s, char sep) {
  std::vector<std::string_view> parts;
  std::size_t start = 0;
  for (;;) {
    const std::size_t end = s.find(sep, start);
    parts.push_back(trim(s.substr(start, end == std::string_view::npos ? std::string_view::npos : end - start)));
    if (end == std::string_view::npos) return parts;
    start = end + 1;
  }
}

std::vector<std::string_view> split_whitespace(std::string_view s) {
  std::vector<std::string_view> parts;
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && (s[i] == ' ' || s[i] == '\t')) ++i;
    const std::size_t start = i;
    while (i < s.size() && s[i] != ' ' && s[i] != '\t') ++i;
    if (i > start) parts.push_back(s.substr(start, i - start));
  }
  return parts;
}

// A number as written, "nan" and "inf" included; nullopt for anything else.
std::optional<double> parse_value(std::string_view text) {
  text = trim(text);
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  double v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return v;
}

// A finite number.
std::optional<double> parse_double(std::string_view text) {
  const std::optional<double> v = parse_value(text);
  if (!v || !std::isfinite(*v)) return std::nullopt;
  return v;
}

std::string in_quotes(std::string_view s) { return "'" + std::string(s) + "'"; }

// Both list formats give (timestamp, file) rows; this checks the order and the files.
struct ListedFrame {
  std::int64_t timestamp_ns;
  std::string path;
  int line;
};

Status check_frames(const std::string& list_file, std::vector<ListedFrame>& listed, std::vector<FrameEntry>& out) {
  for (std::size_t i = 1; i < listed.size(); ++i) {
    if (listed[i].timestamp_ns <= listed[i - 1].timestamp_ns)
      return corrupt_data(at_line(list_file, listed[i].line) + "timestamp " + std::to_string(listed[i].timestamp_ns) +
                          " ns is not after " + std::to_string(listed[i - 1].timestamp_ns) + " ns on line " +
                          std::to_string(listed[i - 1].line) + " (timestamps must strictly increase)");
  }
  for (const ListedFrame& f : listed)
    if (!is_file(f.path)) return not_found(at_line(list_file, f.line) + "frame " + f.path + " is missing");
  out.clear();
  out.reserve(listed.size());
  for (ListedFrame& f : listed) out.push_back({f.timestamp_ns, std::move(f.path)});
  return {};
}

// ---------------------------------------------------------------------------------------------
// EuRoC

// The few YAML shapes EuRoC's sensor.yaml uses: "key: scalar", "key: [a, b, ...]" (possibly over
// several lines) and one level of nested mapping ("T_BS:" then indented "cols: 4" ...).
struct YamlValue {
  int line = 0;
  bool is_list = false;
  std::string scalar;
  std::vector<std::string> items;
  std::map<std::string, YamlValue> children;
};

Status parse_sensor_yaml(const std::string& path, std::map<std::string, YamlValue>& top) {
  std::vector<std::string> lines;
  ALE_RETURN_IF_ERROR(read_lines(path, lines));
  YamlValue* parent = nullptr;  // the mapping that indented lines belong to
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const int line_no = static_cast<int>(i) + 1;
    std::string text = lines[i].substr(0, lines[i].find('#'));
    if (trim(text).empty() || text[0] == '%' || trim(text) == "---") continue;
    // A flow list may continue on the following lines until its ']'.
    if (text.find('[') != std::string::npos) {
      while (text.find(']') == std::string::npos) {
        if (++i >= lines.size()) return corrupt_data(at_line(path, line_no) + "'[' is never closed");
        text += " " + lines[i].substr(0, lines[i].find('#'));
      }
    }
    const std::size_t indent = text.find_first_not_of(' ');
    if (text[indent] == '\t') return corrupt_data(at_line(path, line_no) + "tab in indentation");
    const std::size_t colon = text.find(':');
    if (colon == std::string::npos) return corrupt_data(at_line(path, line_no) + "expected 'key: value'");
    const std::string key(trim(std::string_view(text).substr(0, colon)));
    const std::string_view rest = trim(std::string_view(text).substr(colon + 1));
    if (key.empty()) return corrupt_data(at_line(path, line_no) + "empty key");

    YamlValue value;
    value.line = line_no;
    if (!rest.empty() && rest.front() == '[') {
      if (rest.back() != ']') return corrupt_data(at_line(path, line_no) + "text after ']' in " + in_quotes(key));
      value.is_list = true;
      const std::string_view inner = trim(rest.substr(1, rest.size() - 2));
      if (!inner.empty())
        for (std::string_view item : split(inner, ',')) value.items.emplace_back(item);
    } else {
      std::string_view s = rest;
      if (s.size() >= 2 && (s.front() == '"' || s.front() == '\'') && s.back() == s.front())
        s = s.substr(1, s.size() - 2);
      value.scalar = std::string(s);
    }

    std::map<std::string, YamlValue>* into = &top;
    if (indent > 0) {
      if (parent == nullptr) return corrupt_data(at_line(path, line_no) + "indented " + in_quotes(key) + " belongs to no key");
      into = &parent->children;
    }
    if (into->count(key) != 0) return corrupt_data(at_line(path, line_no) + "key " + in_quotes(key) + " appears twice");
    YamlValue& stored = (*into)[key] = std::move(value);
    if (indent == 0) parent = (rest.empty() ? &stored : nullptr);
  }
  return {};
}

// The numbers of list `key`, which must have exactly `count` of them.
Status yaml_numbers(const std::string& path, const YamlValue& v, const std::string& key, std::size_t count,
                    double* out) {
  if (!v.is_list || v.items.size() != count)
    return corrupt_data(at_line(path, v.line) + in_quotes(key) + " must be a list of " + std::to_string(count) +
                        " numbers");
  for (std::size_t i = 0; i < count; ++i) {
    const std::optional<double> d = parse_double(v.items[i]);
    if (!d) return corrupt_data(at_line(path, v.line) + in_quotes(key) + ": " + in_quotes(v.items[i]) + " is not a number");
    out[i] = *d;
  }
  return {};
}

Status yaml_number(const std::string& path, const YamlValue& v, const std::string& key, double& out) {
  const std::optional<double> d = v.is_list ? std::nullopt : parse_double(v.scalar);
  if (!d) return corrupt_data(at_line(path, v.line) + in_quotes(key) + ": " + in_quotes(v.scalar) + " is not a number");
  out = *d;
  return {};
}

// A 4x4 matrix written as EuRoC writes T_BS: rows, cols (optional, 4) and a row-major data list.
Status read_matrix4(const std::string& path, const YamlValue& m, const std::string& key, std::array<double, 16>& out) {
  const auto child = [&](const char* name) -> const YamlValue* {
    const auto it = m.children.find(name);
    return it == m.children.end() ? nullptr : &it->second;
  };
  const YamlValue* rows = child("rows");
  const YamlValue* cols = child("cols");
  const YamlValue* data = child("data");
  if (data == nullptr) return corrupt_data(at_line(path, m.line) + in_quotes(key) + " has no 'data'");
  double r = 4, c = 4;
  if (rows != nullptr) ALE_RETURN_IF_ERROR(yaml_number(path, *rows, key + ".rows", r));
  if (cols != nullptr) ALE_RETURN_IF_ERROR(yaml_number(path, *cols, key + ".cols", c));
  if (r != 4 || c != 4) return corrupt_data(at_line(path, m.line) + in_quotes(key) + " must be 4x4");
  return yaml_numbers(path, *data, key + ".data", 16, out.data());
}

// The two list formats differ only in how a row is split and how its time is written.
struct ListFormat {
  char separator;  // ',' or ' ' (any run of blanks)
  std::optional<std::int64_t> (*parse_time)(std::string_view);
  const char* columns;    // for messages
  const char* time_unit;  // for messages
};
const ListFormat kEurocList{',', parse_integer_ns, "'timestamp [ns],filename'", "an integer of ns"};
const ListFormat kTumList{' ', parse_seconds_ns, "'timestamp filename'", "a time in seconds"};

// Non-blank, non-comment lines with their 1-based line numbers.
std::vector<std::pair<int, std::string_view>> data_lines(const std::vector<std::string>& lines) {
  std::vector<std::pair<int, std::string_view>> rows;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::string_view line = trim(lines[i]);
    if (!line.empty() && line.front() != '#') rows.emplace_back(static_cast<int>(i) + 1, line);
  }
  return rows;
}

// Reads `list` (rows of time and file name relative to `folder`), checks order and files.
Status read_frame_list(const std::string& list, const std::string& folder, const ListFormat& format,
                       std::vector<FrameEntry>& frames) {
  std::vector<std::string> lines;
  ALE_RETURN_IF_ERROR(read_lines(list, lines));
  std::vector<ListedFrame> listed;
  for (const auto& [line_no, line] : data_lines(lines)) {
    const std::vector<std::string_view> cols =
        format.separator == ',' ? split(line, ',') : split_whitespace(line);
    if (cols.size() != 2)
      return corrupt_data(at_line(list, line_no) + "expected 2 columns " + format.columns + ", found " +
                          std::to_string(cols.size()));
    const std::optional<std::int64_t> t = format.parse_time(cols[0]);
    if (!t) return corrupt_data(at_line(list, line_no) + "timestamp " + in_quotes(cols[0]) + " is not " + format.time_unit);
    if (cols[1].empty()) return corrupt_data(at_line(list, line_no) + "empty file name");
    listed.push_back({*t, join(folder, std::string(cols[1])), line_no});
  }
  if (listed.empty()) return not_found(list + ": lists no frames");
  return check_frames(list, listed, frames);
}

struct EurocPaths {
  std::string cam0;
  std::string groundtruth;
  std::string odometry;  // mav0/odometry0/ when it holds a data.csv
};

// The cam0/ folder for `path` being the folder holding mav0/, mav0/ or cam0/ itself.
std::optional<EurocPaths> find_euroc(const std::string& path) {
  for (const char* sub : {"mav0/cam0", "cam0", ""}) {
    const std::string cam0 = *sub != '\0' ? join(path, sub) : path;
    if (is_file(join(cam0, "data.csv")) && is_dir(join(cam0, "data"))) {
      const std::string gt = join(cam0, "../state_groundtruth_estimate0/data.csv");
      const std::string odometry = join(cam0, "../odometry0");
      return EurocPaths{cam0, is_file(gt) ? fs::path(gt).lexically_normal().string() : std::string(),
                        is_file(join(odometry, "data.csv")) ? fs::path(odometry).lexically_normal().string()
                                                            : std::string()};
    }
  }
  return std::nullopt;
}

// The columns of odometry0/data.csv, by their header names.
enum OdometryColumn { kOdoTime, kOdoX, kOdoY, kOdoTheta, kOdoGyro, kOdoVLeft, kOdoVRight, kOdoColumns };
constexpr const char* kOdometryColumnNames[kOdoColumns] = {"timestamp [ns]", "x [m]",        "y [m]",
                                                           "theta [rad]",    "gyro_z [rad/s]", "v_left [m/s]",
                                                           "v_right [m/s]"};
constexpr const char* kOdometryHeader =
    "'#timestamp [ns],x [m],y [m],theta [rad]' (then optionally 'gyro_z [rad/s]', 'v_left [m/s],v_right [m/s]')";

// The header's columns: where each known column is (-1: absent), checked for the required ones.
Status read_odometry_header(const std::string& file, int line_no, std::string_view header,
                            std::array<int, kOdoColumns>& where, std::size_t& count) {
  where.fill(-1);
  header.remove_prefix(1);  // '#'
  const std::vector<std::string_view> names = split(header, ',');
  count = names.size();
  for (std::size_t i = 0; i < names.size(); ++i) {
    const auto* known = std::find_if(std::begin(kOdometryColumnNames), std::end(kOdometryColumnNames),
                                     [&](const char* n) { return names[i] == n; });
    if (known == std::end(kOdometryColumnNames))
      return corrupt_data(at_line(file, line_no) + "unknown column " + in_quotes(names[i]) + "; expected " +
                          kOdometryHeader);
    int& w = where[static_cast<std::size_t>(known - std::begin(kOdometryColumnNames))];
    if (w >= 0) return corrupt_data(at_line(file, line_no) + "column " + in_quotes(names[i]) + " appears twice");
    w = static_cast<int>(i);
  }
  for (int c : {kOdoTime, kOdoX, kOdoY, kOdoTheta})
    if (where[static_cast<std::size_t>(c)] < 0)
      return corrupt_data(at_line(file, line_no) + "no column " + in_quotes(kOdometryColumnNames[c]) + "; expected " +
                          kOdometryHeader);
  if ((where[kOdoVLeft] < 0) != (where[kOdoVRight] < 0))
    return corrupt_data(at_line(file, line_no) + "'v_left [m/s]' and 'v_right [m/s]' go together");
  return {};
}

Status read_odometry_rows(const std::string& file, std::vector<OdometryRow>& rows) {
  std::vector<std::string> lines;
  ALE_RETURN_IF_ERROR(read_lines(file, lines));
  // The header is the first line that is not blank; later '#' lines are comments.
  std::size_t first = 0;
  while (first < lines.size() && trim(lines[first]).empty()) ++first;
  const int header_line = static_cast<int>(first) + 1;
  if (first == lines.size() || trim(lines[first]).front() != '#')
    return corrupt_data(at_line(file, header_line) + "no header; expected " + kOdometryHeader);
  std::array<int, kOdoColumns> where{};
  std::size_t count = 0;
  ALE_RETURN_IF_ERROR(read_odometry_header(file, header_line, trim(lines[first]), where, count));
  const auto column = [&](const std::vector<std::string_view>& cols, int c) {
    return cols[static_cast<std::size_t>(where[static_cast<std::size_t>(c)])];
  };
  rows.clear();
  int previous_line = 0;
  for (const auto& [line_no, line] : data_lines(lines)) {
    const std::vector<std::string_view> cols = split(line, ',');
    if (cols.size() != count)
      return corrupt_data(at_line(file, line_no) + "expected " + std::to_string(count) + " columns as the header on line " +
                          std::to_string(header_line) + ", found " + std::to_string(cols.size()));
    OdometryRow r;
    const std::optional<std::int64_t> t = parse_integer_ns(column(cols, kOdoTime));
    if (!t)
      return corrupt_data(at_line(file, line_no) + "timestamp " + in_quotes(column(cols, kOdoTime)) +
                          " is not an integer of ns");
    r.timestamp_ns = *t;
    if (!rows.empty() && r.timestamp_ns <= rows.back().timestamp_ns)
      return corrupt_data(at_line(file, line_no) + "timestamp " + std::to_string(r.timestamp_ns) + " ns is not after " +
                          std::to_string(rows.back().timestamp_ns) + " ns on line " + std::to_string(previous_line) +
                          " (timestamps must strictly increase)");
    r.has_gyro = where[kOdoGyro] >= 0;
    r.has_wheels = where[kOdoVLeft] >= 0;
    const std::pair<int, double*> values[] = {{kOdoX, &r.x_m},           {kOdoY, &r.y_m},
                                              {kOdoTheta, &r.theta_rad}, {kOdoGyro, &r.gyro_z_rps},
                                              {kOdoVLeft, &r.v_left_mps}, {kOdoVRight, &r.v_right_mps}};
    for (const auto& [c, out] : values) {
      if (where[static_cast<std::size_t>(c)] < 0) continue;
      const std::optional<double> v = parse_value(column(cols, c));
      if (!v)
        return corrupt_data(at_line(file, line_no) + in_quotes(kOdometryColumnNames[c]) + ": " +
                            in_quotes(column(cols, c)) + " is not a number");
      *out = *v;
    }
    rows.push_back(r);
    previous_line = line_no;
  }
  if (rows.empty()) return corrupt_data(at_line(file, header_line) + "a header and no rows (at least one is needed)");
  return {};
}

Status read_euroc(const EurocPaths& paths, Dataset& ds) {
  ds.format = DatasetFormat::kEuroc;
  ds.folder = paths.cam0;
  ds.list_file = join(paths.cam0, "data.csv");
  ds.groundtruth_file = paths.groundtruth;
  ALE_RETURN_IF_ERROR(read_frame_list(ds.list_file, join(paths.cam0, "data"), kEurocList, ds.frames));
  const std::string yaml = join(paths.cam0, "sensor.yaml");
  if (!is_file(yaml)) return not_found(yaml + ": no such file (the EuRoC camera description)");
  Result<hal::CameraCalibration> calib = read_euroc_sensor_yaml(yaml);
  if (!calib.ok()) return calib.status();
  ds.calibration = *calib;
  ds.width = calib->width;
  ds.height = calib->height;
  if (!paths.odometry.empty()) {
    Result<OdometryTrack> odometry = read_odometry_folder(paths.odometry);
    if (!odometry.ok()) return odometry.status();
    ds.odometry = std::move(*odometry);
  }
  return {};
}

// ---------------------------------------------------------------------------------------------
// TUM

bool has_image_extension(const std::string& name) {
  const std::string ext = fs::path(name).extension().string();
  return ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".PNG" || ext == ".JPG" || ext == ".JPEG";
}

// Frames found by their names: <seconds>.png in `images`, sorted by time.
Status read_tum_folder(const std::string& images, std::vector<FrameEntry>& frames) {
  std::error_code ec;
  std::vector<FrameEntry> found;
  for (fs::directory_iterator it(images, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (!has_image_extension(name) || !is_file(it->path().string())) continue;
    const std::optional<std::int64_t> t = parse_seconds_ns(it->path().stem().string());
    if (!t) return corrupt_data(it->path().string() + ": image name is not a time in seconds (like 1311868169.163498.png)");
    found.push_back({*t, it->path().string()});
  }
  if (ec) return io_error(images + ": cannot list: " + ec.message());
  if (found.empty()) return not_found(images + ": no frames (no rgb.txt and no <seconds>.png images)");
  std::sort(found.begin(), found.end(),
            [](const FrameEntry& a, const FrameEntry& b) { return a.timestamp_ns < b.timestamp_ns; });
  for (std::size_t i = 1; i < found.size(); ++i)
    if (found[i].timestamp_ns == found[i - 1].timestamp_ns)
      return corrupt_data(found[i].path + ": same timestamp as " + found[i - 1].path);
  frames = std::move(found);
  return {};
}

bool folder_has_images(const std::string& folder) {
  std::error_code ec;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec))
    if (has_image_extension(it->path().filename().string())) return true;
  return false;
}

// The first frame's size becomes the dataset's; with a known size (sensor.yaml) they must agree.
Status check_first_frame(Dataset& ds) {
  const Result<io::ImageFileInfo> info = io::probe_image(ds.frames.front().path);
  if (!info.ok()) return info.status();
  if (ds.width == 0) {
    ds.width = info->width;
    ds.height = info->height;
  } else if (info->width != ds.width || info->height != ds.height) {
    return corrupt_data(ds.frames.front().path + ": frame is " + std::to_string(info->width) + "x" +
                        std::to_string(info->height) + " but the camera's resolution is " + std::to_string(ds.width) +
                        "x" + std::to_string(ds.height));
  }
  return {};
}

}  // namespace

std::optional<std::int64_t> parse_integer_ns(std::string_view text) {
  text = trim(text);
  std::int64_t v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (text.empty() || text.front() == '-' || ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return v;
}

std::optional<std::int64_t> parse_seconds_ns(std::string_view text) {
  text = trim(text);
  const std::size_t dot = text.find('.');
  const std::string_view whole = text.substr(0, dot);
  const std::string_view frac = dot == std::string_view::npos ? std::string_view() : text.substr(dot + 1);
  if (whole.empty() || frac.size() > 9 || (dot != std::string_view::npos && frac.empty())) return std::nullopt;
  const std::optional<std::int64_t> seconds = parse_integer_ns(whole);
  if (!seconds || *seconds > std::numeric_limits<std::int64_t>::max() / 1000000000 - 1) return std::nullopt;
  std::int64_t ns = 0;
  for (std::size_t i = 0; i < 9; ++i) {
    if (i < frac.size() && (frac[i] < '0' || frac[i] > '9')) return std::nullopt;
    ns = ns * 10 + (i < frac.size() ? frac[i] - '0' : 0);
  }
  return *seconds * 1000000000 + ns;
}

Result<hal::CameraCalibration> read_euroc_sensor_yaml(const std::string& path) {
  std::map<std::string, YamlValue> top;
  ALE_RETURN_IF_ERROR(parse_sensor_yaml(path, top));
  const auto find = [&](const char* key) -> const YamlValue* {
    const auto it = top.find(key);
    return it == top.end() ? nullptr : &it->second;
  };
  hal::CameraCalibration c;

  if (const YamlValue* model = find("camera_model"); model != nullptr && model->scalar != "pinhole")
    return unsupported(at_line(path, model->line) + "camera_model " + in_quotes(model->scalar) +
                       " is not supported (pinhole only)");

  const YamlValue* intrinsics = find("intrinsics");
  if (intrinsics == nullptr) return not_found(path + ": no 'intrinsics' key (fx, fy, cx, cy)");
  double k[4];
  ALE_RETURN_IF_ERROR(yaml_numbers(path, *intrinsics, "intrinsics", 4, k));
  if (k[0] <= 0 || k[1] <= 0)
    return corrupt_data(at_line(path, intrinsics->line) + "focal lengths must be positive");
  c.fx = k[0];
  c.fy = k[1];
  c.cx = k[2];
  c.cy = k[3];

  const YamlValue* resolution = find("resolution");
  if (resolution == nullptr) return not_found(path + ": no 'resolution' key (width, height)");
  double wh[2];
  ALE_RETURN_IF_ERROR(yaml_numbers(path, *resolution, "resolution", 2, wh));
  if (wh[0] < 1 || wh[1] < 1 || wh[0] > 16384 || wh[1] > 16384 || wh[0] != std::floor(wh[0]) ||
      wh[1] != std::floor(wh[1]))
    return corrupt_data(at_line(path, resolution->line) + "resolution must be two whole numbers in 1..16384");
  c.width = static_cast<int>(wh[0]);
  c.height = static_cast<int>(wh[1]);

  const YamlValue* model = find("distortion_model");
  const YamlValue* coeffs = find("distortion_coefficients");
  if (model != nullptr) {
    if (model->scalar == "radial-tangential" || model->scalar == "radtan") {
      c.distortion_model = hal::DistortionModel::kRadialTangential;
    } else if (model->scalar == "equidistant") {
      c.distortion_model = hal::DistortionModel::kEquidistant;
    } else if (model->scalar == "none") {
      c.distortion_model = hal::DistortionModel::kNone;
    } else {
      return unsupported(at_line(path, model->line) + "distortion_model " + in_quotes(model->scalar) +
                         " is not supported (radial-tangential, equidistant or none)");
    }
  }
  if (c.distortion_model != hal::DistortionModel::kNone) {
    if (coeffs == nullptr) return not_found(path + ": no 'distortion_coefficients' key for " + in_quotes(model->scalar));
    ALE_RETURN_IF_ERROR(yaml_numbers(path, *coeffs, "distortion_coefficients", 4, c.distortion.data()));
  }

  if (const YamlValue* rate = find("rate_hz"); rate != nullptr) {
    ALE_RETURN_IF_ERROR(yaml_number(path, *rate, "rate_hz", c.rate_hz));
    if (c.rate_hz <= 0) return corrupt_data(at_line(path, rate->line) + "rate_hz must be positive");
  }
  if (const YamlValue* t_bs = find("T_BS"); t_bs != nullptr) ALE_RETURN_IF_ERROR(read_matrix4(path, *t_bs, "T_BS", c.T_BS));
  return c;
}

Result<OdometryTrack> read_odometry_folder(const std::string& folder) {
  OdometryTrack track;
  track.list_file = join(folder, "data.csv");
  track.sensor_yaml = join(folder, "sensor.yaml");
  ALE_RETURN_IF_ERROR(read_odometry_rows(track.list_file, track.rows));
  if (!is_file(track.sensor_yaml))
    return not_found(track.sensor_yaml + ": no such file (the odometry description: rate_hz, T_BC)");
  std::map<std::string, YamlValue> top;
  ALE_RETURN_IF_ERROR(parse_sensor_yaml(track.sensor_yaml, top));
  if (const auto rate = top.find("rate_hz"); rate != top.end()) {
    ALE_RETURN_IF_ERROR(yaml_number(track.sensor_yaml, rate->second, "rate_hz", track.rate_hz));
    if (track.rate_hz <= 0) return corrupt_data(at_line(track.sensor_yaml, rate->second.line) + "rate_hz must be positive");
  }
  if (const auto t_bc = top.find("T_BC"); t_bc != top.end()) {
    std::array<double, 16> m{};
    ALE_RETURN_IF_ERROR(read_matrix4(track.sensor_yaml, t_bc->second, "T_BC", m));
    track.T_BC = m;
  }
  return track;
}

Result<Dataset> open_dataset(const std::string& path, const DatasetOptions& options) {
  if (!is_dir(path)) {
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0) return invalid_argument(path + ": not a folder (give the dataset's folder)");
    return not_found(path + ": no such folder");
  }
  Dataset ds;
  if (std::optional<EurocPaths> euroc = find_euroc(path)) {
    if (!options.odometry) euroc->odometry.clear();
    ALE_RETURN_IF_ERROR(read_euroc(*euroc, ds));
  } else {
    ds.format = DatasetFormat::kTum;
    ds.folder = path;
    if (is_file(join(path, "rgb.txt"))) {
      ds.list_file = join(path, "rgb.txt");
      ALE_RETURN_IF_ERROR(read_frame_list(ds.list_file, path, kTumList, ds.frames));
    } else if (is_dir(join(path, "rgb")) || folder_has_images(path)) {
      ALE_RETURN_IF_ERROR(read_tum_folder(is_dir(join(path, "rgb")) ? join(path, "rgb") : path, ds.frames));
    } else {
      return not_found(path + ": no frames: neither EuRoC (mav0/cam0/data.csv) nor TUM (rgb.txt, rgb/<seconds>.png)");
    }
  }
  ALE_RETURN_IF_ERROR(check_first_frame(ds));
  return ds;
}

Result<std::vector<GroundTruthState>> read_euroc_groundtruth(const std::string& path) {
  std::vector<std::string> lines;
  ALE_RETURN_IF_ERROR(read_lines(path, lines));
  std::vector<GroundTruthState> states;
  for (const auto& [line_no, line] : data_lines(lines)) {
    const std::vector<std::string_view> cols = split(line, ',');
    if (cols.size() < 8)
      return corrupt_data(at_line(path, line_no) + "expected at least 8 columns (t, p, q), found " +
                          std::to_string(cols.size()));
    GroundTruthState s;
    const std::optional<std::int64_t> t = parse_integer_ns(cols[0]);
    if (!t) return corrupt_data(at_line(path, line_no) + "timestamp " + in_quotes(cols[0]) + " is not an integer of ns");
    s.timestamp_ns = *t;
    const std::size_t numbers = cols.size() >= 11 ? 10 : 7;
    for (std::size_t c = 1; c <= numbers; ++c) {
      const std::optional<double> v = parse_double(cols[c]);
      if (!v) return corrupt_data(at_line(path, line_no) + "column " + std::to_string(c + 1) + ": " +
                                  in_quotes(cols[c]) + " is not a number");
      if (c <= 3) s.p_wb[c - 1] = *v;
      else if (c <= 7) s.q_wb_wxyz[c - 4] = *v;
      else s.v_wb[c - 8] = *v;
    }
    if (!states.empty() && s.timestamp_ns <= states.back().timestamp_ns)
      return corrupt_data(at_line(path, line_no) + "timestamp " + std::to_string(s.timestamp_ns) +
                          " ns is not after the previous row's");
    states.push_back(s);
  }
  if (states.empty()) return not_found(path + ": no ground-truth rows");
  return states;
}

}  // namespace ale::replay
