#include "app/tools/lib/eval/report.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>
#include <sstream>

#include "app/tools/lib/eval/text.h"

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
constexpr const char* kRefColour = "#1f77b4";
constexpr const char* kSeriesColour = "#333333";
constexpr const char* kRelocColour = "#2ca02c";
constexpr const char* kNewMapColour = "#9467bd";
constexpr const char* kLoopColour = "#ff7f0e";
constexpr const char* kMergeColour = "#17becf";
// A frame-log event is drawn at the estimate's pose with the frame's timestamp; the trajectory
// file and the frame log write the same nanoseconds, so this only absorbs the decimal rounding.
constexpr double kEventMatchS = 1e-4;

using Points = std::vector<std::array<double, 2>>;

struct Range {
  double lo = 0.0;
  double hi = 1.0;
  double span() const { return hi - lo; }
};

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

  enum class Shape { kRing, kSquare, kDiamond, kTriangle };

  // A marker at p (data units); its class names the event.
  void marker(const std::array<double, 2>& p, const char* colour, Shape shape, const char* css_class) {
    const double x = px(p[0]);
    const double y = py(p[1]);
    const char* stroke = "\" fill=\"none\" stroke-width=\"2\" stroke=\"";
    switch (shape) {
      case Shape::kSquare:
        body_ << "<rect class=\"" << css_class << "\" x=\"" << fmt(x - 5.0) << "\" y=\"" << fmt(y - 5.0)
              << "\" width=\"10\" height=\"10" << stroke << colour << "\"/>\n";
        break;
      case Shape::kRing:
        body_ << "<circle class=\"" << css_class << "\" cx=\"" << fmt(x) << "\" cy=\"" << fmt(y) << "\" r=\"6" << stroke
              << colour << "\"/>\n";
        break;
      case Shape::kDiamond:
        body_ << "<polygon class=\"" << css_class << "\" points=\"" << fmt(x) << ',' << fmt(y - 7.0) << ' ' << fmt(x + 7.0)
              << ',' << fmt(y) << ' ' << fmt(x) << ',' << fmt(y + 7.0) << ' ' << fmt(x - 7.0) << ',' << fmt(y) << stroke
              << colour << "\"/>\n";
        break;
      case Shape::kTriangle:  // pointing up, its centroid at p
        body_ << "<polygon class=\"" << css_class << "\" points=\"" << fmt(x) << ',' << fmt(y - 8.0) << ' ' << fmt(x + 7.0)
              << ',' << fmt(y + 4.0) << ' ' << fmt(x - 7.0) << ',' << fmt(y + 4.0) << stroke << colour << "\"/>\n";
        break;
    }
  }

  // A vertical line over the whole plot height at x (data units).
  void vertical(double x, const char* colour, const char* css_class) {
    body_ << "<line class=\"" << css_class << "\" x1=\"" << fmt(px(x), "%.2f") << "\" y1=\"" << kMarginTop << "\" x2=\""
          << fmt(px(x), "%.2f") << "\" y2=\"" << kMarginTop + inner_h() << "\" stroke=\"" << colour
          << "\" stroke-width=\"1.5\"/>\n";
  }

  // A coloured stripe over the whole plot height from x0 to x1 (data units).
  void band(double x0, double x1, const char* colour) {
    body_ << "<rect x=\"" << fmt(px(x0), "%.2f") << "\" y=\"" << kMarginTop << "\" width=\""
          << fmt(px(x1) - px(x0), "%.2f") << "\" height=\"" << inner_h() << "\" fill=\"" << colour << "\"/>\n";
  }

  // Bands have no y values worth a scale.
  void hide_y_ticks() { y_ticks_ = false; }

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
    if (!y_ticks_) return;
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
  bool y_ticks_ = true;
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

// The frame log's events on the estimate: where each relocalised frame was placed, where each
// new map's first pose lies (the first frame with a pose after map_id changed; not the log's
// first map), where each frame a loop was closed on was placed (after the correction), and where
// each frame a map was merged on was placed (in the older map it moved into; that change of map_id
// starts no new map). Events whose frame has no aligned pose (not associated) are counted apart.
struct TrackEvents {
  Points relocalisations;
  Points new_maps;
  Points loops;
  Points merges;
  std::size_t unplaced = 0;
};

TrackEvents track_events(const FrameLog& log, const std::vector<StampedPose>& est, const std::array<int, 2>& axes) {
  TrackEvents events;
  auto place = [&](const FrameRecord& f, Points& into) {
    const auto after = std::lower_bound(est.begin(), est.end(), f.t_s() - kEventMatchS,
                                        [](const StampedPose& p, double t) { return p.t_s < t; });
    if (after == est.end() || after->t_s > f.t_s() + kEventMatchS) {
      ++events.unplaced;
      return;
    }
    into.push_back({after->p_wb[axes[0]], after->p_wb[axes[1]]});
  };
  bool new_map_pending = false;
  for (std::size_t i = 0; i < log.frames.size(); ++i) {
    const FrameRecord& f = log.frames[i];
    const bool merged = log.has_merge_columns && merges_at(log, i) > 0;
    if (i > 0 && f.map_id != log.frames[i - 1].map_id) new_map_pending = !merged;
    if (f.state == TrackingState::kRelocalized) place(f, events.relocalisations);
    if (log.has_loop_columns && loops_closed_at(log, i) > 0) place(f, events.loops);
    if (merged) place(f, events.merges);
    if (new_map_pending && has_pose(f.state)) {
      place(f, events.new_maps);
      new_map_pending = false;
    }
  }
  return events;
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
  if (in.frame_log != nullptr) {
    const TrackEvents events = track_events(*in.frame_log, in.aligned->est, axes);
    for (const auto& p : events.relocalisations) plot.marker(p, kRelocColour, SvgPlot::Shape::kRing, "relocalisation");
    for (const auto& p : events.new_maps) plot.marker(p, kNewMapColour, SvgPlot::Shape::kSquare, "new-map");
    for (const auto& p : events.loops) plot.marker(p, kLoopColour, SvgPlot::Shape::kDiamond, "loop-closure");
    for (const auto& p : events.merges) plot.marker(p, kMergeColour, SvgPlot::Shape::kTriangle, "map-merge");
    plot.legend(2, kRelocColour, "relocalised frame (" + std::to_string(events.relocalisations.size()) + ", rings)");
    plot.legend(3, kNewMapColour,
                "first pose of a new map (" + std::to_string(events.new_maps.size()) + ", squares)" +
                    (events.unplaced > 0 ? "; " + std::to_string(events.unplaced) + " events without an aligned pose" : ""));
    if (in.frame_log->has_loop_columns) {
      plot.legend(4, kLoopColour, "frame a loop was closed on (" + std::to_string(events.loops.size()) + ", diamonds)");
    }
    if (in.frame_log->has_merge_columns) {
      plot.legend(in.frame_log->has_loop_columns ? 5 : 4, kMergeColour,
                  "frame a map was merged on (" + std::to_string(events.merges.size()) + ", triangles)");
    }
  }
  const char* names[] = {"x [m]", "y [m]", "z [m]"};
  return plot.finish(names[axes[0]], names[axes[1]]);
}

// The time axis all plots over time share: the same origin, range and label, so that an error
// peak lines up with the frames around it.
struct TimeAxis {
  double t0 = 0.0;
  Range x;
  std::string label;
};

struct Reference {
  double y = 0.0;
  std::string label;
};

struct YScale {
  double lo = 0.0;
  double min_hi = 0.0;  // counts that are all zero still get a scale of whole numbers
};

// Frames of the log marked by a vertical line each (on the time axis), named in the legend with
// their count.
struct Marks {
  std::vector<double> t;
  const char* colour = kSeriesColour;
  const char* css_class = "";
  std::string name;
};

// The frames for which `is_event(log, i)` holds.
Marks frame_marks(const FrameLog& log, const TimeAxis& axis, bool (*is_event)(const FrameLog&, std::size_t),
                  const char* colour, const char* css_class, const std::string& name) {
  Marks marks{{}, colour, css_class, name};
  for (std::size_t i = 0; i < log.frames.size(); ++i) {
    if (is_event(log, i)) marks.t.push_back(log.frames[i].t_s() - axis.t0);
  }
  return marks;
}

Marks relocalised_frames(const FrameLog& log, const TimeAxis& axis) {
  return frame_marks(
      log, axis, [](const FrameLog& l, std::size_t i) { return l.frames[i].state == TrackingState::kRelocalized; },
      kRelocColour, "relocalisation", "relocalised frame");
}

// nullopt for a log without the loop columns: nothing to mark, not "none closed".
std::optional<Marks> loop_frames(const FrameLog* log, const TimeAxis& axis) {
  if (log == nullptr || !log->has_loop_columns) return std::nullopt;
  return frame_marks(
      *log, axis, [](const FrameLog& l, std::size_t i) { return loops_closed_at(l, i) > 0; }, kLoopColour,
      "loop-closure", "loop closed");
}

// A curve over time, optionally with a dashed horizontal reference line and marked frames.
std::string series_plot(const Points& pts, const TimeAxis& axis, YScale scale, const char* colour,
                        const std::string& y_label, const Reference* reference = nullptr,
                        const std::optional<Marks>& marks = std::nullopt) {
  Range y = range_of({&pts}, 1);
  y.lo = scale.lo;
  y.hi = std::max(y.hi, scale.min_hi);
  if (reference != nullptr) y.hi = std::max(y.hi, reference->y + 0.03 * y.span());
  SvgPlot plot(760, 220, axis.x, y, false);
  int legend_row = 0;
  if (reference != nullptr) {
    plot.polyline({{axis.x.lo, reference->y}, {axis.x.hi, reference->y}}, kRefColour, 1.0, true);
    plot.legend(legend_row++, kRefColour, reference->label);
  }
  if (marks) {
    for (double t : marks->t) plot.vertical(t, marks->colour, marks->css_class);
    plot.legend(legend_row++, marks->colour, marks->name + " (" + std::to_string(marks->t.size()) + ")");
  }
  plot.polyline(pts, colour, 1.2);
  return plot.finish(axis.label, y_label);
}

std::string error_plot(const ReportInput& in, const Points& pts, const TimeAxis& axis) {
  double sum_sq = 0.0;
  for (double e : in.error_values) sum_sq += e * e;
  const double rmse = std::sqrt(sum_sq / static_cast<double>(std::max<std::size_t>(1, pts.size())));
  const Reference line{rmse, "rmse " + fmt(rmse, "%.4g")};
  return series_plot(pts, axis, {}, kEstColour, in.error_label, &line, loop_frames(in.frame_log, axis));
}

Points frame_series(const FrameLog& log, double t0, double (*value)(const FrameRecord&)) {
  Points pts;
  pts.reserve(log.frames.size());
  for (const FrameRecord& f : log.frames) pts.push_back({f.t_s() - t0, value(f)});
  return pts;
}

// One stripe per run of frames in the same category; a frame lasts until the next one (the last
// as long as the one before it). The legend is HTML above the plot, outside the stripes.
std::string band_plot(const FrameLog& log, const TimeAxis& axis, int (*category)(const FrameRecord&),
                      const std::vector<std::pair<std::string, const char*>>& legend, const std::string& y_label) {
  SvgPlot plot(760, 110, axis.x, {0.0, 1.0}, false);
  plot.hide_y_ticks();
  const std::vector<FrameRecord>& f = log.frames;
  std::size_t start = 0;
  for (std::size_t i = 1; i <= f.size(); ++i) {
    if (i < f.size() && category(f[i]) == category(f[start])) continue;
    const double last_length = f.size() > 1 ? f.back().t_s() - f[f.size() - 2].t_s() : 0.0;
    const double end_s = i < f.size() ? f[i].t_s() : f.back().t_s() + last_length;
    plot.band(f[start].t_s() - axis.t0, end_s - axis.t0, legend[static_cast<std::size_t>(category(f[start]))].second);
    start = i;
  }
  std::ostringstream html;
  html << "<div class=\"legend\">";
  for (const auto& [name, colour] : legend) {
    html << "<span class=\"swatch\" style=\"background:" << colour << "\"></span>" << html_escape(name) << " ";
  }
  html << "</div>\n" << plot.finish(axis.label, y_label);
  return html.str();
}

template <class Enum, std::size_t N>
std::vector<std::pair<std::string, const char*>> band_legend(const std::array<const char*, N>& colours) {
  std::vector<std::pair<std::string, const char*>> legend;
  for (std::size_t i = 0; i < N; ++i) legend.emplace_back(to_string(static_cast<Enum>(i)), colours[i]);
  return legend;
}

std::string frame_log_plots(const FrameLog& log, const TimeAxis& axis) {
  // Dark to light for the brightness classes; red for lost, so a loss catches the eye.
  constexpr std::array<const char*, kBrightnessClasses> brightness_colours = {"#252525", "#737373", "#c6dbef",
                                                                               "#fdd835"};
  constexpr std::array<const char*, 5> state_colours = {"#e0e0e0", "#9ecae1", "#74c476", "#d62728", "#fd8d3c"};
  constexpr YScale kCountScale{0.0, 10.0};
  const FrameLogSummary summary = summarize(log);
  std::ostringstream html;
  html << "<h2>Brightness class</h2>\n"
       << band_plot(log, axis, [](const FrameRecord& f) { return static_cast<int>(f.brightness); },
                    band_legend<BrightnessClass>(brightness_colours), "class")
       << "<h2>Mean intensity</h2>\n"
       << series_plot(frame_series(log, axis.t0, [](const FrameRecord& f) { return f.mean; }), axis, {},
                      kSeriesColour, "mean intensity (raw)")
       << "<h2>Features</h2>\n"
       << series_plot(frame_series(log, axis.t0, [](const FrameRecord& f) { return static_cast<double>(f.features); }), axis,
                      kCountScale, kSeriesColour, "features");
  const Reference via_min{static_cast<double>(kViaMinInliers), "VIA threshold " + std::to_string(kViaMinInliers)};
  const Reference p95{summary.frame_time_p95_ms, "p95 " + fmt(summary.frame_time_p95_ms, "%.3g") + " ms"};
  const std::optional<Marks> loops = loop_frames(&log, axis);
  html << "<h2>Inliers</h2>\n"
       << series_plot(frame_series(log, axis.t0, [](const FrameRecord& f) { return static_cast<double>(f.inliers); }), axis,
                      kCountScale, kSeriesColour, "inliers", &via_min)
       << "<h2>Frame time</h2>\n"
       << series_plot(frame_series(log, axis.t0, [](const FrameRecord& f) { return f.frame_time_ms; }), axis,
                      {}, kSeriesColour, "frame time [ms]", &p95, loops)
       << "<h2>Tracking state</h2>\n"
       << band_plot(log, axis, [](const FrameRecord& f) { return static_cast<int>(f.state); },
                    band_legend<TrackingState>(state_colours), "state");
  if (!log.has_slam_columns) return html.str();
  html << "<h2>Map</h2>\n"
       << series_plot(frame_series(log, axis.t0, [](const FrameRecord& f) { return static_cast<double>(f.keyframes); }),
                      axis, kCountScale, kSeriesColour, "keyframes")
       << series_plot(frame_series(log, axis.t0, [](const FrameRecord& f) { return static_cast<double>(f.landmarks); }),
                      axis, kCountScale, kSeriesColour, "map points", nullptr, loops)
       << "<h2>Stage times</h2>\n"
       << series_plot(frame_series(log, axis.t0, [](const FrameRecord& f) { return f.frontend_ms; }), axis, {},
                      kSeriesColour, "front end [ms]")
       << series_plot(frame_series(log, axis.t0, [](const FrameRecord& f) { return f.tracking_ms; }), axis, {},
                      kSeriesColour, "tracking [ms]")
       << series_plot(frame_series(log, axis.t0, [](const FrameRecord& f) { return f.mapping_ms; }), axis, {},
                      kSeriesColour, "mapping [ms]", nullptr, loops);
  if (log.has_place_column) {
    // Place recognition, with a line at each relocalised frame.
    html << "<h2>Place recognition</h2>\n"
         << series_plot(frame_series(log, axis.t0, [](const FrameRecord& f) { return f.place_ms; }), axis, {},
                        kSeriesColour, "place recognition [ms]", nullptr, relocalised_frames(log, axis));
  }
  if (loops) {
    // Loop closing's time (its lookups and corrections), with a line at each frame a loop was closed on.
    html << "<h2>Loop closing</h2>\n"
         << series_plot(frame_series(log, axis.t0, [](const FrameRecord& f) { return f.loop_ms; }), axis, {},
                        kSeriesColour, "loop closing [ms]", nullptr, loops);
  }
  return html.str();
}

Status check_input(const ReportInput& in) {
  const bool trajectory = in.gt != nullptr || in.aligned != nullptr;
  if (trajectory) {
    if (in.gt == nullptr || in.gt->poses.empty() || in.aligned == nullptr || in.aligned->est.empty()) {
      return invalid_argument("report: no poses to draw");
    }
    if (in.error_t_s.size() != in.error_values.size() || in.error_values.empty()) {
      return invalid_argument("report: error times and values differ in size or are empty");
    }
  }
  if (in.frame_log != nullptr) {
    if (in.frame_log->frames.empty()) return invalid_argument("report: frame log " + in.frame_log->name + " is empty");
    if (trajectory && in.gt->format == TrajectoryFormat::kKitti) {
      return invalid_argument("report: " + in.gt->name +
                              " is KITTI (line index as time): cannot share a time axis with a frame log");
    }
  } else if (!trajectory) {
    return invalid_argument("report: neither poses nor a frame log to draw");
  }
  return Status::ok_status();
}

}  // namespace

Result<std::string> render_report_html(const ReportInput& in) {
  ALE_RETURN_IF_ERROR(check_input(in));
  TimeAxis axis;
  Points errors;
  std::vector<const Points*> spans;
  if (in.gt != nullptr) {
    axis.t0 = in.gt->poses.front().t_s;
    axis.label = in.gt->format == TrajectoryFormat::kKitti ? "frame index" : "time since ground-truth start [s]";
    for (std::size_t i = 0; i < in.error_values.size(); ++i) {
      errors.push_back({in.error_t_s[i] - axis.t0, in.error_values[i]});
    }
    spans.push_back(&errors);
  } else {
    axis.t0 = in.frame_log->frames.front().t_s();
    axis.label = "time since first frame [s]";
  }
  Points frame_times;
  if (in.frame_log != nullptr) {
    frame_times = {{in.frame_log->frames.front().t_s() - axis.t0, 0.0}, {in.frame_log->frames.back().t_s() - axis.t0, 0.0}};
    spans.push_back(&frame_times);
  }
  axis.x = range_of(spans, 0);

  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>" << html_escape(in.title)
       << "</title>\n<style>body{font-family:sans-serif;margin:24px;color:#222}"
          "table{border-collapse:collapse;margin-bottom:16px}"
          "td{padding:2px 12px;border-bottom:1px solid #ddd;font-family:monospace}"
          "h2{font-size:16px;margin:20px 0 6px}"
          ".summary{font-size:18px;line-height:1.5}"
          ".legend{font-size:12px;margin:0 0 4px 70px}"
          ".swatch{display:inline-block;width:12px;height:12px;margin:0 4px 0 10px;"
          "vertical-align:middle;border:1px solid #888}</style></head><body>\n"
       << "<h1>" << html_escape(in.title) << "</h1>\n";
  if (!in.summary.empty()) {
    html << "<p class=\"summary\">";
    for (std::size_t i = 0; i < in.summary.size(); ++i) html << (i > 0 ? "<br>\n" : "") << html_escape(in.summary[i]);
    html << "</p>\n<h2>All figures</h2>\n";
  }
  html << "<table>\n";
  for (const auto& [key, value] : in.figures) {
    html << "<tr><td>" << html_escape(key) << "</td><td>" << html_escape(value) << "</td></tr>\n";
  }
  html << "</table>\n";
  if (in.gt != nullptr) {
    html << "<h2>Top view</h2>\n" << top_view(in) << "<h2>Error over time</h2>\n" << error_plot(in, errors, axis);
  }
  if (in.frame_log != nullptr) html << frame_log_plots(*in.frame_log, axis);
  html << "</body></html>\n";
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
