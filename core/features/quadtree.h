// ORB-SLAM-style spatial distribution of corners: split the detection area into nodes, keep
// splitting until there are as many nodes as the budget, keep the strongest corner of each node.
//
// As in ORB-SLAM's DistributeOctTree, nodes are split in whole breadth-first rounds while a round
// fits the budget, then the fullest nodes first until the budget is reached. Where ORB-SLAM keeps
// the overshoot of the last split (up to 3 nodes), we drop the weakest children of that split, so
// a level never exceeds its budget. Nodes are index ranges into one array, so nothing is
// allocated once the scratch has grown.
#pragma once

#include <cstdint>
#include <vector>

#include "core/features/fast.h"

namespace ale::features {

struct QuadtreeScratch {
  struct Node {
    float x0, y0, x1, y1;
    int begin, end;  // range of `order`
  };
  // A corner's position and its index in the input: the splits partition these directly (no
  // indirection through the corner array on every comparison).
  struct Entry {
    std::int16_t x, y;
    std::int32_t index;
  };
  std::vector<Entry> order;
  std::vector<Node> nodes;
  std::vector<Node> next;
  std::vector<int> pick;
};

// Appends at most `budget` corners of `corners`, spread over `area`, to `out`. The area starts as
// max(1, round(width / height)) side-by-side square-ish nodes, as in ORB-SLAM.
void distribute_quadtree(const std::vector<FastCorner>& corners, PixelRect area, int budget,
                         QuadtreeScratch& scratch, std::vector<FastCorner>& out);

}  // namespace ale::features
