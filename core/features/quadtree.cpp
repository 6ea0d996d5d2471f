#include "core/features/quadtree.h"

#include <algorithm>
#include <cmath>

namespace ale::features {

namespace {

using Node = QuadtreeScratch::Node;
using Entry = QuadtreeScratch::Entry;

// For an integer v and a float bound b: v < b exactly when v < ceil(b).
inline int first_not_below(float b) { return static_cast<int>(std::ceil(b)); }

// Splits `n` into its four quadrants (the empty ones dropped), appending them to `nodes`.
void split(Node n, std::vector<Entry>& order, std::vector<Node>& nodes) {
  const float xm = 0.5f * (n.x0 + n.x1);
  const float ym = 0.5f * (n.y0 + n.y1);
  const int xi = first_not_below(xm);
  const int yi = first_not_below(ym);
  Entry* first = order.data() + n.begin;
  Entry* last = order.data() + n.end;
  Entry* mid_y = std::partition(first, last, [yi](const Entry& e) { return e.y < yi; });
  Entry* mid_top = std::partition(first, mid_y, [xi](const Entry& e) { return e.x < xi; });
  Entry* mid_bottom = std::partition(mid_y, last, [xi](const Entry& e) { return e.x < xi; });
  const int base = n.begin;
  const auto at = [&](Entry* p) { return base + static_cast<int>(p - first); };
  const Node quads[4] = {{n.x0, n.y0, xm, ym, at(first), at(mid_top)},
                         {xm, n.y0, n.x1, ym, at(mid_top), at(mid_y)},
                         {n.x0, ym, xm, n.y1, at(mid_y), at(mid_bottom)},
                         {xm, ym, n.x1, n.y1, at(mid_bottom), at(last)}};
  for (const Node& q : quads)
    if (q.end > q.begin) nodes.push_back(q);
}

}  // namespace

void distribute_quadtree(const std::vector<FastCorner>& corners, PixelRect area, int budget,
                         QuadtreeScratch& scratch, std::vector<FastCorner>& out) {
  if (budget <= 0 || corners.empty() || area.width <= 0 || area.height <= 0) return;
  const int n = static_cast<int>(corners.size());
  if (n <= budget) {
    out.insert(out.end(), corners.begin(), corners.end());
    return;
  }
  std::vector<Entry>& order = scratch.order;
  std::vector<Node>& nodes = scratch.nodes;
  order.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const FastCorner& c = corners[static_cast<std::size_t>(i)];
    order[static_cast<std::size_t>(i)] = {c.x, c.y, i};
  }
  nodes.clear();

  const int roots = std::max(1, static_cast<int>(std::lround(static_cast<double>(area.width) / area.height)));
  const float x0 = static_cast<float>(area.x);
  const float y0 = static_cast<float>(area.y);
  const float root_w = static_cast<float>(area.width) / static_cast<float>(roots);
  int begin = 0;
  for (int r = 0; r < roots; ++r) {
    const float rx1 = r + 1 == roots ? x0 + static_cast<float>(area.width) : x0 + root_w * static_cast<float>(r + 1);
    Entry* first = order.data() + begin;
    Entry* last = order.data() + n;
    const int xi = first_not_below(rx1);
    Entry* mid = r + 1 == roots ? last : std::partition(first, last, [xi](const Entry& e) { return e.x < xi; });
    const int end = begin + static_cast<int>(mid - first);
    if (end > begin)
      nodes.push_back({x0 + root_w * static_cast<float>(r), y0, rx1, y0 + static_cast<float>(area.height), begin, end});
    begin = end;
  }

  // Whole rounds while they fit the budget (spatial uniformity), then the fullest nodes first.
  std::size_t last_split_begin = nodes.size();
  for (;;) {
    const int have = static_cast<int>(nodes.size());
    if (have >= budget) break;
    int splittable = 0;
    for (const Node& node : nodes) splittable += node.end - node.begin > 1 ? 1 : 0;
    if (splittable == 0) break;  // every node holds one corner
    if (have + 3 * splittable <= budget) {
      scratch.next.clear();
      for (const Node& node : nodes) {
        if (node.end - node.begin > 1)
          split(node, order, scratch.next);
        else
          scratch.next.push_back(node);
      }
      nodes.swap(scratch.next);
      continue;
    }
    while (static_cast<int>(nodes.size()) < budget) {
      int biggest = -1;
      int most = 1;
      for (int i = 0; i < static_cast<int>(nodes.size()); ++i) {
        const int count = nodes[static_cast<std::size_t>(i)].end - nodes[static_cast<std::size_t>(i)].begin;
        if (count > most) {
          most = count;
          biggest = i;
        }
      }
      if (biggest < 0) break;
      const Node victim = nodes[static_cast<std::size_t>(biggest)];
      nodes.erase(nodes.begin() + biggest);
      last_split_begin = nodes.size();
      split(victim, order, nodes);
    }
    break;
  }

  // The strongest corner per node; when the last split overshot the budget, the strongest nodes.
  std::vector<int>& pick = scratch.pick;
  pick.clear();
  for (const Node& node : nodes) {
    int best = order[static_cast<std::size_t>(node.begin)].index;
    for (int k = node.begin + 1; k < node.end; ++k) {
      const int i = order[static_cast<std::size_t>(k)].index;
      if (corners[static_cast<std::size_t>(i)].score > corners[static_cast<std::size_t>(best)].score) best = i;
    }
    pick.push_back(best);
  }
  if (static_cast<int>(pick.size()) > budget) {
    // The last split overshot by at most 3: drop the weakest of its children.
    const auto first_child = pick.begin() + static_cast<std::ptrdiff_t>(last_split_begin);
    std::sort(first_child, pick.end(), [&](int a, int b) {
      const FastCorner& ca = corners[static_cast<std::size_t>(a)];
      const FastCorner& cb = corners[static_cast<std::size_t>(b)];
      return ca.score != cb.score ? ca.score > cb.score : a < b;
    });
    pick.resize(static_cast<std::size_t>(budget));
  }
  std::sort(pick.begin(), pick.end());
  for (int i : pick) out.push_back(corners[static_cast<std::size_t>(i)]);
}

}  // namespace ale::features
