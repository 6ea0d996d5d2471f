#include "app/tools/lib/eval/summary.h"

#include <cmath>
#include <cstdio>

namespace ale::eval {
namespace {

std::string format(const char* fmt, double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), fmt, v);
  return buf;
}

std::string plural(std::size_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

}  // namespace

std::string round_significant(double v, int digits) {
  if (!std::isfinite(v)) return "n/a";
  if (v == 0.0) return "0";
  const int magnitude = static_cast<int>(std::floor(std::log10(std::abs(v))));
  int decimals = digits - 1 - magnitude;
  // rounding may carry into the next power of ten (9.96 -> 10): one decimal fewer then
  const double rounded = std::round(v * std::pow(10.0, decimals)) / std::pow(10.0, decimals);
  if (std::floor(std::log10(std::abs(rounded))) > magnitude) --decimals;
  if (decimals < 0) decimals = 0;
  std::string s = format(("%." + std::to_string(decimals) + "f").c_str(), v);
  if (s.find('.') != std::string::npos) {
    while (s.back() == '0') s.pop_back();
    if (s.back() == '.') s.pop_back();
  }
  return s;
}

std::string percent(double share) {
  const double p = 100.0 * share;
  std::string s;
  for (int decimals = 0; decimals <= 3; ++decimals) {
    s = format(("%." + std::to_string(decimals) + "f").c_str(), p);
    const double shown = std::stod(s);
    if (!((shown == 100.0 && share < 1.0) || (shown == 0.0 && share > 0.0))) break;
  }
  return s;
}

double path_length_m(const std::vector<StampedPose>& poses) {
  double length = 0.0;
  for (std::size_t i = 1; i < poses.size(); ++i) length += (poses[i].p_wb - poses[i - 1].p_wb).norm();
  return length;
}

std::vector<std::string> summary_lines(const SummaryInput& in) {
  std::vector<std::string> lines;
  if (in.ate_m != nullptr) {
    std::string line = "ATE " + round_significant(100.0 * in.ate_m->rmse, 2) + " cm (RMSE";
    if (in.alignment != Alignment::kNone) line += std::string(" after ") + to_string(in.alignment) + " alignment";
    line += ")";
    if (in.path_m > 0.0) {
      line += ", " + round_significant(100.0 * in.ate_m->rmse / in.path_m, 2) + " % of the " +
              round_significant(in.path_m, 2) + " m path";
    }
    lines.push_back(line + " over " + plural(in.pairs, "pose", "poses"));
  }
  if (in.frames != nullptr) {
    const FrameLogSummary& f = *in.frames;
    const auto tracked = static_cast<std::size_t>(std::lround(f.tracked_share * static_cast<double>(f.frames)));
    lines.push_back("tracked " + percent(f.tracked_share) + " % of the frames (" + std::to_string(tracked) + " of " +
                    std::to_string(f.frames) + "), " + plural(f.tracking_losses, "tracking loss", "tracking losses") +
                    ", " + plural(f.relocalisations, "relocalisation", "relocalisations") + ", " +
                    (f.loops_logged ? plural(f.loops_closed, "loop closed", "loops closed") + ", " : "") +
                    (f.merges_logged ? plural(f.merges, "map merged", "maps merged") + ", " : "") +
                    plural(f.maps, "map", "maps"));
    lines.push_back("frame time " + round_significant(f.frame_time_median_ms, 2) + " ms median, " +
                    round_significant(f.frame_time_p95_ms, 2) + " ms p95" +
                    (f.loops_closed > 0 ? ", " + round_significant(f.loop_frame_time_max_ms, 2) +
                                              " ms at the longest loop closure"
                                        : "") +
                    " (on this machine)");
  } else if (in.ate_m != nullptr) {
    lines.push_back("the estimate covers " + percent(in.coverage) + " % of the ground truth's time, " +
                    plural(in.losses, "tracking loss", "tracking losses"));
  }
  return lines;
}

}  // namespace ale::eval
