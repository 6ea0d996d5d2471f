// ale-calibrate's HTML report, in the style of ale-eval report (one self-contained page, inline
// SVG, no scripts): the summary, the parameters with their standard deviations, the coverage of
// the image by the corners, the per-view reprojection errors and the rejected views.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "core/base/status.h"
#include "app/tools/lib/calib/calibration.h"

namespace ale::calib {

struct ReportInput {
  std::string title;
  std::vector<std::pair<std::string, std::string>> figures;  // summary lines
  LensModel model = LensModel::kPinholeRadTan;
  const Calibration* calibration = nullptr;
  std::vector<std::string> view_names;                  // the views used, as `views`
  std::vector<std::vector<Eigen::Vector2d>> views;      // their corners
  std::vector<std::pair<std::string, std::string>> rejected;  // file, why
  Coverage coverage;
};

// kInvalidArgument when the calibration is missing or the view lists differ in size.
Result<std::string> render_report_html(const ReportInput& input);
Status write_report(const std::string& path, const ReportInput& input);

}  // namespace ale::calib
