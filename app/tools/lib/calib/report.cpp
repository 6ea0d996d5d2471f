#include "app/tools/lib/calib/report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "app/tools/lib/eval/text.h"
#include "app/tools/lib/render/sensor_yaml.h"

namespace ale::calib {

namespace {

using eval::html_escape;

std::string fmt(double v, const char* format) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

// A colour per view, cycling through ten distinct hues.
const char* view_colour(std::size_t v) {
  static const char* kColours[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
                                   "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"};
  return kColours[v % 10];
}

// The image, its grid cells shaded by whether they hold a corner, every view's corners.
std::string coverage_svg(const ReportInput& in) {
  const render::PinholeCamera& cam = in.calibration->camera;
  const double scale = 640.0 / cam.width;
  const int w = 640;
  const int h = static_cast<int>(std::lround(cam.height * scale));
  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << w + 2 << "\" height=\"" << h + 2
      << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  const Coverage& c = in.coverage;
  for (int gy = 0; gy < c.rows; ++gy)
    for (int gx = 0; gx < c.cols; ++gx) {
      const bool covered = c.counts[static_cast<std::size_t>(gy * c.cols + gx)] > 0;
      svg << "<rect x=\"" << fmt(1 + gx * w / static_cast<double>(c.cols), "%.1f") << "\" y=\""
          << fmt(1 + gy * h / static_cast<double>(c.rows), "%.1f") << "\" width=\"" << fmt(w / static_cast<double>(c.cols), "%.1f")
          << "\" height=\"" << fmt(h / static_cast<double>(c.rows), "%.1f") << "\" fill=\""
          << (covered ? "#e8f5e9" : "#fde0dc") << "\" stroke=\"#ccc\"/>\n";
    }
  for (std::size_t v = 0; v < in.views.size(); ++v)
    for (const Eigen::Vector2d& p : in.views[v])
      svg << "<circle cx=\"" << fmt(1 + p.x() * scale, "%.1f") << "\" cy=\"" << fmt(1 + p.y() * scale, "%.1f")
          << "\" r=\"1.6\" fill=\"" << view_colour(v) << "\"/>";
  svg << "\n<rect x=\"1\" y=\"1\" width=\"" << w << "\" height=\"" << h << "\" fill=\"none\" stroke=\"#000\"/>\n</svg>\n";
  return svg.str();
}

// One bar per view: its RMS reprojection error, the overall RMS as a dashed line.
std::string view_errors_svg(const ReportInput& in) {
  const Calibration& cal = *in.calibration;
  const std::size_t n = cal.view_rms_px.size();
  const int left = 60, bottom = 30, top = 10, bar = std::max(4, std::min(24, static_cast<int>(600 / std::max<std::size_t>(n, 1))));
  const int w = left + static_cast<int>(n) * bar + 20;
  const int h = 220;
  const double top_value = std::max(1e-6, 1.15 * *std::max_element(cal.view_rms_px.begin(), cal.view_rms_px.end()));
  const auto y_of = [&](double e) { return top + (h - top - bottom) * (1.0 - e / top_value); };
  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << w << "\" height=\"" << h
      << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  for (std::size_t v = 0; v < n; ++v) {
    const double y = y_of(cal.view_rms_px[v]);
    svg << "<rect x=\"" << left + static_cast<int>(v) * bar + 1 << "\" y=\"" << fmt(y, "%.1f") << "\" width=\"" << bar - 2
        << "\" height=\"" << fmt(h - bottom - y, "%.1f") << "\" fill=\"" << view_colour(v) << "\"><title>"
        << html_escape(in.view_names[v]) << ": " << fmt(cal.view_rms_px[v], "%.3f") << " px</title></rect>\n";
  }
  const double y_rms = y_of(cal.rms_px);
  svg << "<line x1=\"" << left << "\" x2=\"" << w - 10 << "\" y1=\"" << fmt(y_rms, "%.1f") << "\" y2=\"" << fmt(y_rms, "%.1f")
      << "\" stroke=\"#000\" stroke-dasharray=\"6 4\"/>\n"
      << "<text x=\"" << left - 6 << "\" y=\"" << fmt(y_rms + 4, "%.1f") << "\" text-anchor=\"end\">" << fmt(cal.rms_px, "%.3f")
      << "</text>\n<text x=\"" << left - 6 << "\" y=\"" << top + 10 << "\" text-anchor=\"end\">" << fmt(top_value, "%.2f")
      << "</text>\n<line x1=\"" << left << "\" x2=\"" << w - 10 << "\" y1=\"" << h - bottom << "\" y2=\"" << h - bottom
      << "\" stroke=\"#000\"/>\n<text x=\"" << left << "\" y=\"" << h - 8 << "\">views in the order used (hover: file, px); y: RMS px</text>\n</svg>\n";
  return svg.str();
}

}  // namespace

Result<std::string> render_report_html(const ReportInput& in) {
  if (in.calibration == nullptr) return invalid_argument("calibration report: no calibration");
  const Calibration& cal = *in.calibration;
  if (in.views.size() != in.view_names.size() || in.views.size() != cal.view_rms_px.size() || in.views.empty())
    return invalid_argument("calibration report: the views, their names and their errors differ in number");
  if (in.coverage.counts.size() != static_cast<std::size_t>(in.coverage.cols * in.coverage.rows))
    return invalid_argument("calibration report: the coverage grid is incomplete");
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>" << html_escape(in.title)
       << "</title>\n<style>body{font-family:sans-serif;margin:24px;color:#222}"
          "table{border-collapse:collapse;margin-bottom:16px}"
          "td,th{padding:2px 12px;border-bottom:1px solid #ddd;font-family:monospace;text-align:left}"
          "h2{font-size:16px;margin:20px 0 6px}</style></head><body>\n"
       << "<h1>" << html_escape(in.title) << "</h1>\n<table>\n";
  for (const auto& [key, value] : in.figures)
    html << "<tr><td>" << html_escape(key) << "</td><td>" << html_escape(value) << "</td></tr>\n";
  html << "</table>\n<h2>Parameters (one standard deviation)</h2>\n<table>\n";
  const std::array<const char*, 8> names = parameter_names(in.model);
  const double values[8] = {cal.camera.fx, cal.camera.fy, cal.camera.cx, cal.camera.cy,
                            cal.camera.coeffs[0], cal.camera.coeffs[1], cal.camera.coeffs[2], cal.camera.coeffs[3]};
  for (std::size_t k = 0; k < 8; ++k)
    html << "<tr><td>" << names[k] << "</td><td>" << fmt(values[k], k < 4 ? "%.3f px" : "%.6f") << "</td><td>&plusmn; "
         << fmt(cal.stddev[k], k < 4 ? "%.3f px" : "%.6f") << "</td></tr>\n";
  html << "</table>\n<h2>Coverage: " << fmt(100.0 * in.coverage.share, "%.0f") << " % of the " << in.coverage.cols << " x "
       << in.coverage.rows << " cells hold a corner</h2>\n"
       << "<p>Every corner used, coloured by view; red cells hold none (the lens is extrapolated there).</p>\n"
       << coverage_svg(in) << "<h2>Reprojection error per view</h2>\n" << view_errors_svg(in)
       << "<table><tr><th>view</th><th>RMS px</th></tr>\n";
  for (std::size_t v = 0; v < in.views.size(); ++v)
    html << "<tr><td>" << html_escape(in.view_names[v]) << "</td><td>" << fmt(cal.view_rms_px[v], "%.3f") << "</td></tr>\n";
  html << "</table>\n<h2>Rejected images: " << in.rejected.size() << "</h2>\n";
  if (!in.rejected.empty()) {
    html << "<table><tr><th>image</th><th>why</th></tr>\n";
    for (const auto& [name, why] : in.rejected)
      html << "<tr><td>" << html_escape(name) << "</td><td>" << html_escape(why) << "</td></tr>\n";
    html << "</table>\n";
  }
  html << "</body></html>\n";
  return html.str();
}

Status write_report(const std::string& path, const ReportInput& input) {
  Result<std::string> html = render_report_html(input);
  if (!html.ok()) return html.status();
  return render::write_text_file(path, *html);
}

}  // namespace ale::calib
