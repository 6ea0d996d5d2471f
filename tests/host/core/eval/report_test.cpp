#include "core/eval/report.h"

#include <gtest/gtest.h>

#include <string>

namespace ale::eval {
namespace {

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

struct Fixture {
  Trajectory gt;
  PosePairs pairs;
  ReportInput input;

  Fixture() {
    gt.name = "gt.txt";
    for (int k = 0; k < 20; ++k) {
      StampedPose p;
      p.t_s = k;
      p.p_wb = Eigen::Vector3d(k, 0.1 * k * k, 0.0);  // planar in x-y: the view drops z
      gt.poses.push_back(p);
    }
    pairs.gt = gt.poses;
    pairs.est = gt.poses;
    pairs.est.erase(pairs.est.begin() + 8, pairs.est.begin() + 14);  // a 7 s gap
    input.title = "ATE <se3>";
    input.figures = {{"ate_rmse", "0.5"}, {"estimate", "a&b.txt"}};
    input.gt = &gt;
    input.aligned = &pairs;
    input.max_gap_s = 2.0;
    for (const StampedPose& p : pairs.est) {
      input.error_t_s.push_back(p.t_s);
      input.error_values.push_back(0.5);
    }
    input.error_label = "ATE [m]";
  }
};

TEST(ReportTest, PageHasBothPlotsEscapedTextAndABrokenEstimatePath) {
  Fixture f;
  const Result<std::string> html = render_report_html(f.input);
  ASSERT_TRUE(html.ok()) << html.status().to_string();
  EXPECT_EQ(count(*html, "<svg"), 2u);
  EXPECT_NE(html->find("ATE &lt;se3&gt;"), std::string::npos);
  EXPECT_NE(html->find("a&amp;b.txt"), std::string::npos);
  EXPECT_NE(html->find(">x [m]<"), std::string::npos);
  EXPECT_NE(html->find(">y [m]<"), std::string::npos);
  EXPECT_NE(html->find("rmse 0.5"), std::string::npos);
  // Ground truth, the estimate in two runs (split at the gap), rmse line and error curve.
  EXPECT_EQ(count(*html, "<polyline"), 5u);
}

TEST(ReportTest, RejectsMissingOrMismatchedInput) {
  Fixture f;
  f.input.error_values.pop_back();
  EXPECT_FALSE(render_report_html(f.input).ok());
  Fixture g;
  g.input.aligned = nullptr;
  EXPECT_FALSE(render_report_html(g.input).ok());
  Fixture h;
  EXPECT_FALSE(write_report("/nonexistent/dir/report.html", h.input).ok());
}

}  // namespace
}  // namespace ale::eval
