#include "core/frontend/sequence_match.h"

#include <string>

#include "core/frontend/frame_path.h"

namespace ale::frontend {
namespace {

template <class Field>
double mean_of(const std::vector<features::PairMatchFigures>& pairs, Field field) {
  if (pairs.empty()) return 0.0;
  double sum = 0.0;
  for (const features::PairMatchFigures& p : pairs) sum += field(p);
  return sum / static_cast<double>(pairs.size());
}

}  // namespace

double GapFigures::mean_keypoints() const {
  return mean_of(pairs, [](const features::PairMatchFigures& p) { return 0.5 * (p.keypoints_a + p.keypoints_b); });
}
double GapFigures::mean_matches() const {
  return mean_of(pairs, [](const features::PairMatchFigures& p) { return p.matches; });
}
double GapFigures::mean_inliers() const {
  return mean_of(pairs, [](const features::PairMatchFigures& p) { return p.inliers; });
}

Result<std::vector<GapFigures>> match_sequence(const std::vector<GrayImage>& frames,
                                               const features::ExtractorConfig& config, const std::vector<int>& gaps,
                                               const features::PairMatchParams& params) {
  for (int g : gaps)
    if (g < 1) return invalid_argument("match_sequence: gap " + std::to_string(g) + " must be >= 1");
  for (const GrayImage& f : frames)
    if (f.width != frames.front().width || f.height != frames.front().height)
      return invalid_argument("match_sequence: frames of " + std::to_string(frames.front().width) + "x" +
                              std::to_string(frames.front().height) + " and " + std::to_string(f.width) + "x" +
                              std::to_string(f.height));
  FramePath path;
  ALE_RETURN_IF_ERROR(path.configure(config));
  std::vector<std::vector<features::Keypoint>> kps(frames.size());
  std::vector<std::vector<features::Descriptor>> desc(frames.size());
  for (std::size_t i = 0; i < frames.size(); ++i) ALE_RETURN_IF_ERROR(path.extract(frames[i].view(), kps[i], desc[i]));
  std::vector<GapFigures> out;
  features::PairMatchScratch scratch;
  for (int g : gaps) {
    GapFigures gf;
    gf.gap = g;
    const std::size_t step = static_cast<std::size_t>(g);
    for (std::size_t i = 0; i + step < frames.size(); ++i) {
      Result<features::PairMatchFigures> f = features::match_pair(kps[i], desc[i], kps[i + step], desc[i + step], params, scratch);
      if (!f.ok()) return f.status();
      gf.pairs.push_back(*f);
    }
    out.push_back(std::move(gf));
  }
  return out;
}

}  // namespace ale::frontend
