#include "core/features/orb.h"

#include <string>

namespace ale::features {

namespace {

Status range_error(const char* key, const std::string& why) {
  return invalid_argument(std::string("features.") + key + ": " + why);
}

}  // namespace

const char* to_string(ExtractorMode m) {
  switch (m) {
    case ExtractorMode::kAle: return "ale";
    case ExtractorMode::kBaseline: return "baseline";
    case ExtractorMode::kClahe: return "clahe";
  }
  return "?";
}

Result<ExtractorMode> parse_extractor_mode(const std::string& s) {
  if (s == "ale") return ExtractorMode::kAle;
  if (s == "baseline") return ExtractorMode::kBaseline;
  if (s == "clahe") return ExtractorMode::kClahe;
  return invalid_argument("features.mode: '" + s + "' is not one of ale, baseline, clahe");
}

Status validate(const ExtractorConfig& c) {
  if (c.num_features < 1 || c.num_features > 100000) return range_error("num_features", "must be 1..100000");
  if (c.num_levels < 1 || c.num_levels > kMaxLevels)
    return range_error("num_levels", "must be 1.." + std::to_string(kMaxLevels));
  if (!(c.scale_factor > 1.0 && c.scale_factor <= 4.0)) return range_error("scale_factor", "must be in (1, 4]");
  if (c.cell_size_px < 8 || c.cell_size_px > 1000) return range_error("cell_size_px", "must be 8..1000");
  if (c.t_low < 1 || c.t_low > 254) return range_error("t_low", "must be 1..254");
  if (c.t_high < c.t_low || c.t_high > 254) return range_error("t_high", "must be t_low..254");
  if (c.t_higher <= c.t_high || c.t_higher > 254) return range_error("t_higher", "must be t_high+1..254");
  if (c.clahe_everywhere.tiles_x < 1 || c.clahe_everywhere.tiles_y < 1 || c.clahe_everywhere.tiles_x > 254 ||
      c.clahe_everywhere.tiles_y > 254)
    return range_error("clahe_everywhere", "tiles must be 1..254");
  enhance::EnhanceParams cell = c.enhance;
  cell.clahe = c.cell_clahe;
  ALE_RETURN_IF_ERROR(enhance::validate(c.enhance));
  ALE_RETURN_IF_ERROR(enhance::validate(cell));
  return {};
}

}  // namespace ale::features
