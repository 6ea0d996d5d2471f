#include "core/eval/report.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace ale::eval {
namespace {

constexpr int kMarginLeft = 70;
constexpr int kMarginRight = 20;
constexpr int kMarginTop = 20;
constexpr int kMarginBottom = 45;
// Polylines are thinned to about this many points: a 200 Hz ground truth over minutes has tens
// of thousands, more than a plot can show and enough to make the page slow.
constexpr std::size_t kMaxPolylinePoints = 4000;
constexpr const char* kGtColour = "#8c8c8c";
constexpr const char* kEstColour = "#d62728";

using Points = std::vector<std::array<double, 2>>;

struct Range {
  double lo = 0.0;
  double hi = 1.0;
  double span() const { return hi - lo; }
};

std::string html_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string fmt(double v, const char* format = "%.1f") {
  char buf[64];
  std::snprintf(buf, sizeof(buf), format, v);
  return buf;
}

Range range_of(const std::vector<const Points*>& sets, int axis) {
  Range r{INFINITY, -INFINITY};
  for (const Points* pts : sets) {
    for (const auto& p : *pts) {
      r.lo = std::min(r.lo, p[axis]);
      r.hi = std::max(r.hi, p[axis]);
    }
  }
  if (!(r.hi > r.lo)) {  // one point or a constant: give the axis some extent
    const double mid = std::isfinite(r.lo) ? r.lo : 0.0;
    r = {mid - 0.5, mid + 0.5};
  }
  const double pad = 0.03 * r.span();
  return {r.lo - pad, r.hi + pad};
}

// A tick step of 1, 2 or 5 times a power of ten giving four to eight ticks.
double tick_step(double span) {
  const double raw = span / 8.0;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0}) {
    if (m * power >= raw) return m * power;
  }
  return 10.0 * power;
}

class SvgPlot {
 public:
  SvgPlot(int width, int height, Range x, Range y, bool equal_aspect)
      : width_(width), height_(height), x_(x), y_(y) {
    if (equal_aspect) {
      // Same metres per pixel on both axes: widen the range that would be stretched.
      const double per_px = std::max(x_.span() / inner_w(), y_.span() / inner_h());
      x_ = widened(x_, per_px * inner_w());
      y_ = widened(y_, per_px * inner_h());
    }
  }

  void polyline(const Points& pts, const char* colour, double stroke_px, bool dashed = false) {
    if (pts.empty()) return;
    const std::size_t stride = (pts.size() + kMaxPolylinePoints - 1) / kMaxPolylinePoints;
    body_ << "<polyline fill=\"none\" stroke=\"" << colour << "\" stroke-width=\"" << stroke_px << "\""
          << (dashed ? " stroke-dasharray=\"6 4\"" : "") << " points=\"";
    for (std::size_t i = 0; i < pts.size(); i += stride) point(pts[i]);
    if ((pts.size() - 1) % stride != 0) point(pts.back());
    body_ << "\"/>\n";
  }

  void legend(int row, const char* colour, const std::string& text) {
    const int y = kMarginTop + 18 + 18 * row;
    body_ << "<line x1=\"" << kMarginLeft + 12 << "\" y1=\"" << y - 4 << "\" x2=\"" << kMarginLeft + 36
          << "\" y2=\"" << y - 4 << "\" stroke=\"" << colour << "\" stroke-width=\"2.5\"/>"
          << "<text x=\"" << kMarginLeft + 42 << "\" y=\"" << y << "\">" << html_escape(text) << "</text>\n";
  }

  std::string finish(const std::string& x_label, const std::string& y_label) const {
    std::ostringstream svg;
    svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width_ << "\" height=\"" << height_
        << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
        << "<rect x=\"" << kMarginLeft << "\" y=\"" << kMarginTop << "\" width=\"" << inner_w()
        << "\" height=\"" << inner_h() << "\" fill=\"#fff\" stroke=\"#000\"/>\n";
    axis_ticks(svg);
    svg << "<clipPath id=\"c" << width_ << height_ << "\"><rect x=\"" << kMarginLeft << "\" y=\""
        << kMarginTop << "\" width=\"" << inner_w() << "\" height=\"" << inner_h() << "\"/></clipPath>\n"
        << "<g clip-path=\"url(#c" << width_ << height_ << ")\">\n"
        << body_.str() << "</g>\n"
        << "<text x=\"" << kMarginLeft + inner_w() / 2 << "\" y=\"" << height_ - 8
        << "\" text-anchor=\"middle\">" << html_escape(x_label) << "</text>\n"
        << "<text transform=\"translate(16," << kMarginTop + inner_h() / 2
        << ") rotate(-90)\" text-anchor=\"middle\">" << html_escape(y_label) << "</text>\n"
        << "</svg>\n";
    return svg.str();
  }

 private:
  int inner_w() const { return width_ - kMarginLeft - kMarginRight; }
  int inner_h() const { return height_ - kMarginTop - kMarginBottom; }
  static Range widened(Range r, double span) {
    const double mid = 0.5 * (r.lo + r.hi);
    return {mid - 0.5 * span, mid + 0.5 * span};
  }
  double px(double x) const { return kMarginLeft + (x - x_.lo) / x_.span() * inner_w(); }
  double py(double y) const { return kMarginTop + (y_.hi - y) / y_.span() * inner_h(); }
  void point(const std::array<double, 2>& p) { body_ << fmt(px(p[0])) << ',' << fmt(py(p[1])) << ' '; }

  void axis_ticks(std::ostringstream& svg) const {
    const double step_x = tick_step(x_.span());
    for (double v = std::ceil(x_.lo / step_x) * step_x; v <= x_.hi; v += step_x) {
      const double x = px(v);
      svg << "<line x1=\"" << fmt(x) << "\" y1=\"" << kMarginTop << "\" x2=\"" << fmt(x) << "\" y2=\""
          << kMarginTop + inner_h() << "\" stroke=\"#e5e5e5\"/>"
          << "<text x=\"" << fmt(x) << "\" y=\"" << kMarginTop + inner_h() + 16
          << "\" text-anchor=\"middle\">" << fmt(std::abs(v) < 1e-12 ? 0.0 : v, "%g") << "</text>\n";
    }
    const double step_y = tick_step(y_.span());
    for (double v = std::ceil(y_.lo / step_y) * step_y; v <= y_.hi; v += step_y) {
      const double y = py(v);
      svg << "<line x1=\"" << kMarginLeft << "\" y1=\"" << fmt(y) << "\" x2=\"" << kMarginLeft + inner_w()
          << "\" y2=\"" << fmt(y) << "\" stroke=\"#e5e5e5\"/>"
          << "<text x=\"" << kMarginLeft - 6 << "\" y=\"" << fmt(y + 4) << "\" text-anchor=\"end\">"
          << fmt(std::abs(v) < 1e-12 ? 0.0 : v, "%g") << "</text>\n";
    }
  }

  int width_;
  int height_;
  Range x_;
  Range y_;
  std::ostringstream body_;
};

// The two axes along which the ground truth extends most, in x, y, z order: the top view of a
// ground robot or a drone is x-y, of KITTI's camera frame x-z.
std::array<int, 2> view_axes(const Trajectory& gt) {
  Eigen::Vector3d lo = gt.poses.front().p_wb;
  Eigen::Vector3d hi = lo;
  for (const StampedPose& p : gt.poses) {
    lo = lo.cwiseMin(p.p_wb);
    hi = hi.cwiseMax(p.p_wb);
  }
  const Eigen::Vector3d extent = hi - lo;
  int drop = 2;
  for (int a = 0; a < 3; ++a) {
    if (extent[a] < extent[drop]) drop = a;
  }
  return drop == 0 ? std::array<int, 2>{1, 2} : drop == 1 ? std::array<int, 2>{0, 2} : std::array<int, 2>{0, 1};
}

Points project(const std::vector<StampedPose>& poses, const std::array<int, 2>& axes) {
  Points pts;
  pts.reserve(poses.size());
  for (const StampedPose& p : poses) pts.push_back({p.p_wb[axes[0]], p.p_wb[axes[1]]});
  return pts;
}

// The estimate as separate runs, split where it has a gap (tracking lost) so that no straight
// line is drawn across the gap.
std::vector<Points> estimate_runs(const std::vector<StampedPose>& est, const std::array<int, 2>& axes,
                                  double max_gap_s) {
  std::vector<Points> runs(1);
  for (std::size_t i = 0; i < est.size(); ++i) {
    if (i > 0 && max_gap_s > 0.0 && est[i].t_s - est[i - 1].t_s > max_gap_s) runs.emplace_back();
    runs.back().push_back({est[i].p_wb[axes[0]], est[i].p_wb[axes[1]]});
  }
  return runs;
}

std::string top_view(const ReportInput& in) {
  const std::array<int, 2> axes = view_axes(*in.gt);
  const Points gt = project(in.gt->poses, axes);
  const std::vector<Points> runs = estimate_runs(in.aligned->est, axes, in.max_gap_s);
  std::vector<const Points*> all = {&gt};
  for (const Points& r : runs) all.push_back(&r);
  SvgPlot plot(760, 560, range_of(all, 0), range_of(all, 1), true);
  // The ground truth wider and lighter, so that it shows beside an estimate lying on it.
  plot.polyline(gt, kGtColour, 3.0);
  for (const Points& r : runs) plot.polyline(r, kEstColour, 1.2);
  plot.legend(0, kGtColour, "ground truth");
  plot.legend(1, kEstColour, "estimate (aligned)");
  const char* names[] = {"x [m]", "y [m]", "z [m]"};
  return plot.finish(names[axes[0]], names[axes[1]]);
}

std::string error_plot(const ReportInput& in) {
  const double t0 = in.gt->poses.front().t_s;
  Points pts;
  double sum_sq = 0.0;
  for (std::size_t i = 0; i < in.error_values.size(); ++i) {
    pts.push_back({in.error_t_s[i] - t0, in.error_values[i]});
    sum_sq += in.error_values[i] * in.error_values[i];
  }
  const double rmse = std::sqrt(sum_sq / static_cast<double>(std::max<std::size_t>(1, pts.size())));
  Range x = range_of({&pts}, 0);
  Range y = range_of({&pts}, 1);
  y.lo = 0.0;  // errors are magnitudes: show them from zero
  SvgPlot plot(760, 300, x, y, false);
  plot.polyline({{x.lo, rmse}, {x.hi, rmse}}, "#1f77b4", 1.0, true);
  plot.polyline(pts, kEstColour, 1.2);
  plot.legend(0, "#1f77b4", "rmse " + fmt(rmse, "%.4g"));
  const bool frames = in.gt->format == TrajectoryFormat::kKitti;
  return plot.finish(frames ? "frame index" : "time since ground-truth start [s]", in.error_label);
}

}  // namespace

Result<std::string> render_report_html(const ReportInput& in) {
  if (in.gt == nullptr || in.gt->poses.empty() || in.aligned == nullptr || in.aligned->est.empty()) {
    return invalid_argument("report: no poses to draw");
  }
  if (in.error_t_s.size() != in.error_values.size() || in.error_values.empty()) {
    return invalid_argument("report: error times and values differ in size or are empty");
  }
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>" << html_escape(in.title)
       << "</title>\n<style>body{font-family:sans-serif;margin:24px;color:#222}"
          "table{border-collapse:collapse;margin-bottom:16px}"
          "td{padding:2px 12px;border-bottom:1px solid #ddd;font-family:monospace}"
          "h2{font-size:16px;margin:20px 0 6px}</style></head><body>\n"
       << "<h1>" << html_escape(in.title) << "</h1>\n<table>\n";
  for (const auto& [key, value] : in.figures) {
    html << "<tr><td>" << html_escape(key) << "</td><td>" << html_escape(value) << "</td></tr>\n";
  }
  html << "</table>\n<h2>Top view</h2>\n" << top_view(in) << "<h2>Error over time</h2>\n"
       << error_plot(in) << "</body></html>\n";
  return html.str();
}

Status write_report(const std::string& path, const ReportInput& input) {
  Result<std::string> html = render_report_html(input);
  if (!html.ok()) return html.status();
  std::ofstream out(path, std::ios::binary);
  if (!out) return io_error(path + ": cannot create report file");
  out << *html;
  out.close();
  if (!out) return io_error(path + ": write failed");
  return Status::ok_status();
}

}  // namespace ale::eval
