// ale-eval: trajectory accuracy the way the field measures it (agrees with evo).
//
//   ale-eval ate --gt FILE --est FILE [--align se3|sim3|none] [--max-dt S] [--format F] ...
//   ale-eval rpe --gt FILE --est FILE [--delta N] [--delta-unit frames|m] [--align ...] ...
//   ale-eval report --frame-log FILE.csv --out FILE.html
//   ale-eval odometry --dataset DIR --out FILE.tum [--times odometry|frames]
//
// Prints `key value` lines, or with --print summary the few lines a person reads first (ATE in cm
// and % of the path, share tracked, frame time; app/tools/lib/eval/summary.h) and where the report
// is. Exit status: 0 ok, 1 bad or unusable data, 2 bad usage.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "app/tools/lib/eval/align.h"
#include "app/tools/lib/eval/associate.h"
#include "app/tools/lib/eval/frame_log.h"
#include "app/tools/lib/eval/metrics.h"
#include "app/tools/lib/eval/odometry.h"
#include "app/tools/lib/eval/report.h"
#include "app/tools/lib/eval/summary.h"
#include "app/tools/lib/eval/trajectory.h"

namespace {

using ale::Result;
using ale::Status;
namespace ev = ale::eval;

constexpr int kExitData = 1;
constexpr int kExitUsage = 2;

constexpr const char* kUsage =
    "usage:\n"
    "  ale-eval ate --gt FILE --est FILE [--align se3|sim3|none] [--max-dt S] [options]\n"
    "  ale-eval rpe --gt FILE --est FILE [--delta N] [--delta-unit frames|m]\n"
    "               [--pairs-from est|gt] [--align none|se3|sim3] [--max-dt S] [options]\n"
    "  ale-eval report --frame-log FILE.csv --out FILE.html [--print figures|summary]\n"
    "  ale-eval odometry --dataset DIR --out FILE.tum [--times odometry|frames]\n"
    "      the dataset's wheel odometry (mav0/odometry0/) as the camera's trajectory: the\n"
    "      base pose (x, y, theta on the floor) composed with its sensor.yaml's T_BC, at the\n"
    "      odometry's own timestamps or interpolated at the frames' (cam0) timestamps\n"
    "options:\n"
    "  --format tum|euroc|kitti|auto   format of both files (default auto)\n"
    "  --gt-format F, --est-format F   format of one file\n"
    "  --max-dt S      largest time difference for associating poses (default 0.01 s)\n"
    "  --max-gap S     gap in the estimate counted as a tracking loss (default 5x its median\n"
    "                  pose spacing)\n"
    "  --duplicates error|skip   a repeated timestamp is an error (default) or skipped\n"
    "  --report FILE.html        also write an HTML page with plots (top view, error)\n"
    "  --frame-log FILE.csv      the run's per-frame log (ale-slamd --frame-log): print its\n"
    "                  figures and add its plots over time to the report\n"
    "  --at-time S     (ate) also print the aligned position error of the pose nearest to\n"
    "                  time S (within --max-dt): at_time_s, at_time_error_m\n"
    "  --print figures|summary   all figures as `key value` lines (default), or a short\n"
    "                  summary (ATE in cm and % of the path, share tracked, frame time) and\n"
    "                  where the report is; the report opens with the same summary\n"
    "ate aligns with se3 by default, rpe does not align by default. KITTI files have no\n"
    "timestamps: the line index is the time.\n";

struct Args {
  std::string command;
  std::map<std::string, std::string> values;
};

// A usage problem (exit 2) or a data problem (exit 1), with its message.
struct Failure {
  int exit_code;
  std::string message;
};

int fail(const Failure& f) {
  std::fprintf(stderr, "ale-eval: %s\n", f.message.c_str());
  if (f.exit_code == kExitUsage) std::fputs(kUsage, stderr);
  return f.exit_code;
}

Failure usage(std::string message) { return {kExitUsage, std::move(message)}; }
Failure data(const Status& s) { return {kExitData, s.message()}; }

bool parse_args(int argc, char** argv, Args* args, Failure* failure) {
  if (argc < 2) {
    *failure = usage("missing command (ate, rpe, report or odometry)");
    return false;
  }
  args->command = argv[1];
  const std::set<std::string> common = {"--gt", "--est", "--align", "--max-dt", "--format", "--gt-format",
                                        "--est-format", "--max-gap", "--duplicates", "--report", "--frame-log",
                                        "--print"};
  const std::set<std::string> rpe_only = {"--delta", "--delta-unit", "--pairs-from"};
  const std::set<std::string> report_only = {"--frame-log", "--out", "--print"};
  const std::set<std::string> odometry_only = {"--dataset", "--out", "--times"};
  const bool report = args->command == "report";
  const bool odometry = args->command == "odometry";
  if (args->command != "ate" && args->command != "rpe" && !report && !odometry) {
    *failure = usage("unknown command '" + args->command + "' (expected ate, rpe, report or odometry)");
    return false;
  }
  for (int i = 2; i < argc; ++i) {
    const std::string key = argv[i];
    const bool known = report     ? report_only.count(key) > 0
                       : odometry ? odometry_only.count(key) > 0
                                  : common.count(key) > 0 || (args->command == "rpe" && rpe_only.count(key) > 0) ||
                                        (args->command == "ate" && key == "--at-time");
    if (!known) {
      *failure = usage("unknown option '" + key + "' for " + args->command);
      return false;
    }
    if (i + 1 >= argc) {
      *failure = usage("option " + key + " needs a value");
      return false;
    }
    if (!args->values.emplace(key, argv[++i]).second) {
      *failure = usage("option " + key + " given twice");
      return false;
    }
  }
  const std::vector<const char*> required = report     ? std::vector<const char*>{"--frame-log", "--out"}
                                             : odometry ? std::vector<const char*>{"--dataset", "--out"}
                                                        : std::vector<const char*>{"--gt", "--est"};
  for (const char* key : required) {
    if (args->values.count(key) == 0) {
      *failure = usage(std::string("missing ") + key + (std::string(key) == "--dataset" ? " DIR" : " FILE"));
      return false;
    }
  }
  const auto print = args->values.find("--print");
  if (print != args->values.end() && print->second != "figures" && print->second != "summary") {
    *failure = usage("--print must be figures or summary, got '" + print->second + "'");
    return false;
  }
  const auto times = args->values.find("--times");
  if (times != args->values.end() && times->second != "odometry" && times->second != "frames") {
    *failure = usage("--times must be odometry or frames, got '" + times->second + "'");
    return false;
  }
  return true;
}

std::string value_or(const Args& args, const std::string& key, const std::string& fallback) {
  const auto it = args.values.find(key);
  return it == args.values.end() ? fallback : it->second;
}

bool parse_number(const Args& args, const std::string& key, double fallback, double* out,
                  Failure* failure) {
  const auto it = args.values.find(key);
  if (it == args.values.end()) {
    *out = fallback;
    return true;
  }
  char* end = nullptr;
  *out = std::strtod(it->second.c_str(), &end);
  if (it->second.empty() || *end != '\0' || !std::isfinite(*out)) {
    *failure = usage(key + " needs a number, got '" + it->second + "'");
    return false;
  }
  return true;
}

// Unwraps a Result from parsing an option's value (usage error) into *out.
template <class T>
bool option_value(Result<T> parsed, T* out, Failure* failure) {
  if (!parsed.ok()) {
    *failure = usage(parsed.status().message());
    return false;
  }
  *out = *parsed;
  return true;
}

using Figures = std::vector<std::pair<std::string, std::string>>;

void add(Figures* figures, const std::string& key, double value) {
  char text[64];
  std::snprintf(text, sizeof(text), "%.12g", value);
  figures->emplace_back(key, text);
}

void add(Figures* figures, const std::string& key, std::size_t value) {
  figures->emplace_back(key, std::to_string(value));
}

void add_frame_log_figures(Figures* figures, const ev::FrameLogSummary& s) {
  add(figures, "frames", s.frames);
  for (std::size_t c = 0; c < ev::kBrightnessClasses; ++c) {
    add(figures, std::string("share_") + ale::to_string(static_cast<ale::BrightnessClass>(c)), s.brightness_share[c]);
  }
  add(figures, "features_mean", s.features_mean);
  add(figures, "via", s.via);
  add(figures, "via_frames", s.via_frames);
  add(figures, "frame_time_mean_ms", s.frame_time_mean_ms);
  add(figures, "frame_time_median_ms", s.frame_time_median_ms);
  add(figures, "frame_time_p95_ms", s.frame_time_p95_ms);
  add(figures, "frame_time_max_ms", s.frame_time_max_ms);
  add(figures, "tracking_losses", s.tracking_losses);
  add(figures, "relocalisations", s.relocalisations);
  add(figures, "tracked_share", s.tracked_share);
  add(figures, "maps", s.maps);
  add(figures, "keyframes_last", static_cast<std::size_t>(s.keyframes_last));
  add(figures, "landmarks_last", static_cast<std::size_t>(s.landmarks_last));
  add(figures, "frontend_mean_ms", s.frontend_mean_ms);
  add(figures, "tracking_mean_ms", s.tracking_mean_ms);
  add(figures, "mapping_mean_ms", s.mapping_mean_ms);
  add(figures, "place_mean_ms", s.place_mean_ms);
  add(figures, "place_max_ms", s.place_max_ms);
  add(figures, "loops_closed", s.loops_closed);
  add(figures, "loop_mean_ms", s.loop_mean_ms);
  add(figures, "loop_max_ms", s.loop_max_ms);
  add(figures, "loop_frame_time_max_ms", s.loop_frame_time_max_ms);
  add(figures, "merges", s.merges);
  add(figures, "merges_refused", s.merges_refused);
}

// What --print asks for: the figures, or the summary and where the report is (if one is written).
void print(const Args& args, const Figures& figures, const std::vector<std::string>& summary,
           const std::string& report_path) {
  if (value_or(args, "--print", "figures") == "figures") {
    for (const auto& [key, value] : figures) std::printf("%s %s\n", key.c_str(), value.c_str());
    return;
  }
  for (const std::string& line : summary) std::printf("%s\n", line.c_str());
  if (!report_path.empty()) std::printf("report: %s\n", report_path.c_str());
}

void add_stats(Figures* figures, const std::string& prefix, const ev::ErrorStats& s) {
  const std::pair<const char*, double> fields[] = {{"rmse", s.rmse}, {"mean", s.mean},
                                                   {"median", s.median}, {"std", s.std},
                                                   {"min", s.min}, {"max", s.max}, {"sse", s.sse}};
  for (const auto& [name, value] : fields) add(figures, prefix + name, value);
}

struct Options {
  ev::ReadOptions gt_read;
  ev::ReadOptions est_read;
  ev::Alignment alignment = ev::Alignment::kSe3;
  double max_dt_s = 0.01;
  double max_gap_s = 0.0;
  ev::RpeOptions rpe;
};

bool parse_options(const Args& args, Options* o, Failure* failure) {
  ev::TrajectoryFormat both = ev::TrajectoryFormat::kAuto;
  const std::string default_align = args.command == "ate" ? "se3" : "none";
  std::string pairs_from;
  if (!option_value(ev::parse_format(value_or(args, "--format", "auto")), &both, failure) ||
      !option_value(ev::parse_format(value_or(args, "--gt-format", ev::to_string(both))), &o->gt_read.format, failure) ||
      !option_value(ev::parse_format(value_or(args, "--est-format", ev::to_string(both))), &o->est_read.format, failure) ||
      !option_value(ev::parse_alignment(value_or(args, "--align", default_align)), &o->alignment, failure) ||
      !option_value(ev::parse_delta_unit(value_or(args, "--delta-unit", "frames")), &o->rpe.unit, failure) ||
      !parse_number(args, "--max-dt", 0.01, &o->max_dt_s, failure) ||
      !parse_number(args, "--max-gap", 0.0, &o->max_gap_s, failure) ||
      !parse_number(args, "--delta", 1.0, &o->rpe.delta, failure)) {
    return false;
  }
  const std::string duplicates = value_or(args, "--duplicates", "error");
  if (duplicates != "error" && duplicates != "skip") {
    *failure = usage("--duplicates must be error or skip, got '" + duplicates + "'");
    return false;
  }
  o->gt_read.skip_duplicate_times = o->est_read.skip_duplicate_times = duplicates == "skip";
  pairs_from = value_or(args, "--pairs-from", "est");
  if (pairs_from != "est" && pairs_from != "gt") {
    *failure = usage("--pairs-from must be est or gt, got '" + pairs_from + "'");
    return false;
  }
  o->rpe.pairs_from_gt = pairs_from == "gt";
  if (o->max_dt_s < 0.0) {
    *failure = usage("--max-dt must be >= 0");
    return false;
  }
  return true;
}

// The optional --frame-log, read into *log; false with *failure set when it cannot be used.
bool read_frame_log_option(const Args& args, std::optional<ev::FrameLog>* log, Failure* failure) {
  const auto path = args.values.find("--frame-log");
  if (path == args.values.end()) return true;
  Result<ev::FrameLog> read = ev::read_frame_log(path->second);
  if (!read.ok()) {
    *failure = data(read.status());
    return false;
  }
  *log = std::move(*read);
  return true;
}

Status write_report(const std::string& path, ev::ReportInput* report, const Figures& figures,
                    const Figures& header) {
  report->figures = header;
  report->figures.insert(report->figures.end(), figures.begin(), figures.end());
  return ev::write_report(path, *report);
}

int run_report(const Args& args) {
  std::optional<ev::FrameLog> log;
  Failure failure{0, ""};
  if (!read_frame_log_option(args, &log, &failure)) return fail(failure);
  Figures figures;
  const ev::FrameLogSummary frames = ev::summarize(*log);
  add_frame_log_figures(&figures, frames);
  ev::SummaryInput summary;
  summary.frames = &frames;
  ev::ReportInput report;
  report.title = "Frame log";
  report.summary = ev::summary_lines(summary);
  report.frame_log = &*log;
  const std::string& out = args.values.at("--out");
  const Status written = write_report(out, &report, figures, {{"frame log", log->name}});
  if (!written.ok()) return fail(data(written));
  print(args, figures, report.summary, out);
  return 0;
}

// The dataset's odometry as the camera's trajectory, written as TUM.
int run_odometry(const Args& args) {
  const std::string& dir = args.values.at("--dataset");
  Result<ale::replay::Dataset> dataset = ale::replay::open_dataset(dir);
  if (!dataset.ok()) return fail(data(dataset.status()));
  if (!dataset->odometry)
    return fail({kExitData, dir + ": no wheel odometry (mav0/odometry0/data.csv) in this dataset"});
  std::vector<std::int64_t> at_ns;
  const bool at_frames = value_or(args, "--times", "odometry") == "frames";
  if (at_frames)
    for (const ale::replay::FrameEntry& f : dataset->frames) at_ns.push_back(f.timestamp_ns);
  Result<ev::Trajectory> trajectory = ev::odometry_camera_trajectory(*dataset->odometry, at_ns);
  if (!trajectory.ok()) return fail(data(trajectory.status()));
  const std::string comment = "camera poses from the wheel odometry of " + dataset->odometry->list_file +
                              " composed with T_BC of " + dataset->odometry->sensor_yaml +
                              (at_frames ? ", interpolated at the frames' times" : ", at the odometry's times");
  const std::string& out = args.values.at("--out");
  std::FILE* f = std::fopen(out.c_str(), "w");
  const std::string text = ev::tum_text(*trajectory, comment);
  const bool written = f != nullptr && std::fwrite(text.data(), 1, text.size(), f) == text.size();
  if (f != nullptr && std::fclose(f) != 0) return fail({kExitData, out + ": cannot write"});
  if (!written) return fail({kExitData, out + ": cannot write"});
  std::printf("poses %zu\nfrom %s\nto %s\n", trajectory->poses.size(), dataset->odometry->list_file.c_str(), out.c_str());
  return 0;
}

int run(const Args& args) {
  if (args.command == "report") return run_report(args);
  if (args.command == "odometry") return run_odometry(args);
  Options o;
  Failure failure{0, ""};
  if (!parse_options(args, &o, &failure)) return fail(failure);
  std::optional<ev::FrameLog> log;
  if (!read_frame_log_option(args, &log, &failure)) return fail(failure);

  Result<ev::Trajectory> gt = ev::read_trajectory(args.values.at("--gt"), o.gt_read);
  if (!gt.ok()) return fail(data(gt.status()));
  Result<ev::Trajectory> est = ev::read_trajectory(args.values.at("--est"), o.est_read);
  if (!est.ok()) return fail(data(est.status()));
  Result<ev::PosePairs> pairs = ev::associate(*gt, *est, o.max_dt_s);
  if (!pairs.ok()) return fail(data(pairs.status()));
  Result<ev::Sim3> alignment = ev::align_estimate(o.alignment, &*pairs);
  if (!alignment.ok()) return fail(data(alignment.status()));
  Result<ev::CoverageResult> coverage = ev::compute_coverage(*gt, *est, o.max_gap_s);
  if (!coverage.ok()) return fail(data(coverage.status()));

  for (const ev::Trajectory* t : {&*gt, &*est}) {
    if (t->duplicates_skipped > 0) {
      std::fprintf(stderr, "ale-eval: %s: skipped %zu poses with a repeated timestamp\n",
                   t->name.c_str(), t->duplicates_skipped);
    }
  }
  Figures figures;
  add(&figures, "pairs", pairs->gt.size());
  add(&figures, "scale", alignment->scale);
  ev::ReportInput report;
  ev::SummaryInput summary;
  summary.alignment = o.alignment;
  summary.pairs = pairs->gt.size();
  summary.path_m = ev::path_length_m(pairs->gt);
  summary.coverage = coverage->coverage;
  summary.losses = coverage->losses;
  report.gt = &*gt;
  report.aligned = &*pairs;
  report.max_gap_s = coverage->max_gap_s;
  ev::ErrorStats ate_m;
  if (args.command == "ate") {
    Result<ev::AteResult> ate = ev::compute_ate(*pairs);
    if (!ate.ok()) return fail(data(ate.status()));
    ate_m = ate->trans_m;
    summary.ate_m = &ate_m;
    add_stats(&figures, "ate_", ate->trans_m);
    add_stats(&figures, "ate_rot_", ate->rot_deg);
    report.title = std::string("ATE, alignment ") + ev::to_string(o.alignment);
    report.error_t_s = ate->t_s;
    report.error_values = ate->trans_errors_m;
    report.error_label = "ATE translation [m]";
    if (args.values.count("--at-time")) {
      double at = 0.0;
      if (!parse_number(args, "--at-time", 0.0, &at, &failure)) return fail(failure);
      std::size_t best = ate->t_s.size();
      for (std::size_t i = 0; i < ate->t_s.size(); ++i)
        if (best == ate->t_s.size() || std::abs(ate->t_s[i] - at) < std::abs(ate->t_s[best] - at)) best = i;
      if (best == ate->t_s.size() || std::abs(ate->t_s[best] - at) > o.max_dt_s)
        return fail({kExitData, "--at-time " + args.values.at("--at-time") + ": no pose pair within --max-dt of it"});
      add(&figures, "at_time_s", ate->t_s[best]);
      add(&figures, "at_time_error_m", ate->trans_errors_m[best]);
    }
  } else {
    Result<ev::RpeResult> rpe = ev::compute_rpe(*pairs, o.rpe);
    if (!rpe.ok()) return fail(data(rpe.status()));
    add(&figures, "rpe_pairs", rpe->pairs.size());
    add_stats(&figures, "rpe_trans_", rpe->trans_m);
    add_stats(&figures, "rpe_rot_", rpe->rot_deg);
    report.title = "RPE, delta " + value_or(args, "--delta", "1") + " " + ev::to_string(o.rpe.unit);
    for (const auto& [i, j] : rpe->pairs) report.error_t_s.push_back(pairs->gt[j].t_s);
    report.error_values = rpe->trans_errors_m;
    report.error_label = "RPE translation [m]";
  }
  add(&figures, "coverage", coverage->coverage);
  add(&figures, "losses", coverage->losses);
  add(&figures, "max_gap_s", coverage->max_gap_s);
  Figures header = {{"ground truth", gt->name}, {"estimate", est->name}};
  ev::FrameLogSummary frames;
  if (log) {
    frames = ev::summarize(*log);
    add_frame_log_figures(&figures, frames);
    summary.frames = &frames;
    report.frame_log = &*log;
    header.emplace_back("frame log", log->name);
  }
  report.summary = ev::summary_lines(summary);

  const std::string report_path = value_or(args, "--report", "");
  if (!report_path.empty()) {
    const Status written = write_report(report_path, &report, figures, header);
    if (!written.ok()) return fail(data(written));
  }
  print(args, figures, report.summary, report_path);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      std::fputs(kUsage, stdout);
      return 0;
    }
  }
  Args args;
  Failure failure{0, ""};
  if (!parse_args(argc, argv, &args, &failure)) return fail(failure);
  return run(args);
}
