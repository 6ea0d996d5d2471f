#include "core/features/orb.h"

#include <string>


namespace ale::features {

namespace {

constexpr const char* kLevelEnhanceNames[] = {"never", "non_normal_frames", "always", nullptr};  // by LevelEnhance

constexpr ConfigField kClaheEverywhereFields[] = {
    number<&enhance::ClaheParams::tiles_x>("tiles_x", 1, 254, "grid columns"),
    number<&enhance::ClaheParams::tiles_y>("tiles_y", 1, 254, "grid rows"),
    number<&enhance::ClaheParams::clip_limit>("clip_limit", 0, 256, "clip limit (OpenCV units)"),
};
constexpr ConfigTable kClaheEverywhereTable = table_of<enhance::ClaheParams>(kClaheEverywhereFields);

// Not constexpr: the nested tables come from core/enhance by function.
const ConfigField kExtractorFields[] = {
    number<&ExtractorConfig::num_features>("num_features", 1, 100000, "feature budget over all pyramid levels"),
    number<&ExtractorConfig::num_levels>("num_levels", 1, kMaxLevels, "pyramid levels"),
    number<&ExtractorConfig::scale_factor>("scale_factor", 1.01, 4, "scale between levels"),
    number<&ExtractorConfig::cell_size_px>("cell_size_px", 8, 1000, "FAST grid cell edge"),
    number<&ExtractorConfig::t_high>("t_high", 1, 254, "FAST threshold of the first pass (>= t_low)"),
    number<&ExtractorConfig::t_higher>("t_higher", 1, 254, "FAST threshold after the cell CLAHE (> t_high)"),
    number<&ExtractorConfig::t_low>("t_low", 1, 254, "FAST threshold of the last pass, on the plain cell"),
    flag<&ExtractorConfig::cell_retry>("cell_retry", "ALE: the CLAHE retry of the per-cell ladder"),
    flag<&ExtractorConfig::retry_normal_frames>("retry_normal_frames",
                                                "ALE: the cell retry also on frames graded normal (article)"),
    number<&ExtractorConfig::noise_gate>("noise_gate", 0, 64,
                                         "ALE: candidates need a plain score of this times the noise sigma"),
    number<&ExtractorConfig::bright_min_sigma>("bright_min_sigma", 0, 256,
                                               "ALE: a bright frame with at least this sigma is treated as normal"),
    number<&ExtractorConfig::denoise>("denoise", 0, 2,
                                      "ALE: 3x3 binomial before detection: 0 off, 1 extremely dark, 2 not normal"),
    choice<&ExtractorConfig::level_enhance>("level_enhance", kLevelEnhanceNames,
                                            "ALE: when the per-level contrast-guided CLAHE runs"),
    nested<&ExtractorConfig::enhance>("enhance", enhance::enhance_params_table()),
    nested<&ExtractorConfig::cell_clahe>("cell_clahe", enhance::level_clahe_table()),
    nested<&ExtractorConfig::clahe_everywhere>("clahe_everywhere", kClaheEverywhereTable),
};
const ConfigTable kExtractorTable = table_of<ExtractorConfig>(kExtractorFields);

}  // namespace

const ConfigTable& extractor_config_table() { return kExtractorTable; }

const char* to_string(ExtractorMode m) {
  switch (m) {
    case ExtractorMode::kAle: return "ale";
    case ExtractorMode::kBaseline: return "baseline";
    case ExtractorMode::kClahe: return "clahe";
    case ExtractorMode::kHe: return "he";
    case ExtractorMode::kGamma: return "gamma";
  }
  return "?";
}

Result<ExtractorMode> parse_extractor_mode(const std::string& s) {
  if (s == "ale") return ExtractorMode::kAle;
  if (s == "baseline" || s == "off") return ExtractorMode::kBaseline;
  if (s == "clahe") return ExtractorMode::kClahe;
  if (s == "he") return ExtractorMode::kHe;
  if (s == "gamma") return ExtractorMode::kGamma;
  return invalid_argument("features.mode: '" + s + "' is not one of ale, baseline (off), clahe, he, gamma");
}

Status validate(const ExtractorConfig& c) {
  ALE_RETURN_IF_ERROR(check_ranges(kExtractorTable, &c));
  if (c.t_high < c.t_low)
    return invalid_argument("t_high: " + std::to_string(c.t_high) + " must be >= t_low (" + std::to_string(c.t_low) + ")");
  if (c.t_higher <= c.t_high)
    return invalid_argument("t_higher: " + std::to_string(c.t_higher) + " must be > t_high (" +
                            std::to_string(c.t_high) + ")");
  if (Status s = enhance::validate(c.enhance); !s.ok()) return invalid_argument("enhance." + s.message());
  return enhance::validate(c.cell_clahe, "cell_clahe.");
}

}  // namespace ale::features
