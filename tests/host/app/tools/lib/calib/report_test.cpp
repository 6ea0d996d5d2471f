// ale-calibrate's HTML report: the figures, parameters, coverage picture and per-view errors of a
// calibration on one self-contained page; inputs that do not fit together are an error, not a
// page.
#include <gtest/gtest.h>

#include <string>

#include "app/tools/lib/calib/report.h"

namespace ale::calib {
namespace {

Calibration two_view_calibration() {
  Calibration c;
  c.camera.width = 640;
  c.camera.height = 480;
  c.camera.fx = 330.0;
  c.camera.fy = 331.0;
  c.camera.distortion = render::PinholeCamera::Distortion::kEquidistant;
  c.camera.coeffs = {0.02, -0.01, 0.004, -0.001};
  c.view_rms_px = {0.12, 0.34};
  c.rms_px = 0.25;
  c.corners = 4;
  return c;
}

ReportInput input_for(const Calibration& c) {
  ReportInput in;
  in.title = "Camera calibration: <cam>.yaml";
  in.figures = {{"views used", "2 of 3 images"}};
  in.model = LensModel::kFisheye;
  in.calibration = &c;
  in.view_names = {"a.png", "b&c.png"};
  in.views = {{{10.0, 10.0}, {600.0, 400.0}}, {{320.0, 240.0}, {100.0, 450.0}}};
  in.rejected = {{"d.png", "no board: not all 9x6 inner corners found"}};
  in.coverage = corner_coverage(in.views, 640, 480);
  return in;
}

TEST(CalibrationReport, HoldsTheFiguresAndPictures) {
  const Calibration c = two_view_calibration();
  const ReportInput in = input_for(c);
  const Result<std::string> html = render_report_html(in);
  ASSERT_TRUE(html.ok()) << html.status().message();
  EXPECT_NE(html->find("Camera calibration: &lt;cam&gt;.yaml"), std::string::npos);  // escaped
  EXPECT_NE(html->find("b&amp;c.png"), std::string::npos);
  EXPECT_NE(html->find("<td>k4</td>"), std::string::npos);  // the fisheye's names
  EXPECT_NE(html->find("Coverage: 8 % of the 8 x 6 cells"), std::string::npos);  // 4 corners, 4 cells of 48
  EXPECT_NE(html->find("no board: not all 9x6 inner corners found"), std::string::npos);
  EXPECT_EQ(html->find("<script"), std::string::npos);
  std::size_t svgs = 0;
  for (std::size_t at = html->find("<svg"); at != std::string::npos; at = html->find("<svg", at + 1)) ++svgs;
  EXPECT_EQ(svgs, 2u);  // coverage, per-view errors
}

TEST(CalibrationReport, RefusesInputsThatDoNotFit) {
  const Calibration c = two_view_calibration();
  ReportInput in = input_for(c);
  in.view_names.pop_back();
  EXPECT_FALSE(render_report_html(in).ok());
  in = input_for(c);
  in.calibration = nullptr;
  EXPECT_FALSE(render_report_html(in).ok());
  in = input_for(c);
  in.coverage.counts.clear();
  EXPECT_FALSE(render_report_html(in).ok());
}

}  // namespace
}  // namespace ale::calib
