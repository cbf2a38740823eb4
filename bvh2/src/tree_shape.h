#pragma once
// Depth and leaf count of a binary tree stored as flat nodes with `first`
// (left child; right = first + 1) and `count` (0 = inner): BVH2 and spheres.
#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

namespace simdbvh::detail {

struct TreeShape {
    int depth = 0;  // root only = 1
    std::size_t leaves = 0;
};

template <class Node, class Alloc>
TreeShape tree_shape(const std::vector<Node, Alloc>& nodes) {
    TreeShape s;
    if (nodes.empty()) return s;
    // The builders put children after their parent: one pass in index order
    // with a depth per node (depth <= kMaxDepth fits a byte). Any other
    // order falls back to the stack walk below.
    std::vector<std::uint8_t> depth(nodes.size(), 0);
    depth[0] = 1;
    bool ordered = true;
    for (std::size_t i = 0; i < nodes.size() && ordered; ++i) {
        const Node& n = nodes[i];
        const int d = depth[i];
        if (d == 0) {
            ordered = false;
            break;
        }  // not reached from the root in index order
        s.depth = std::max(s.depth, d);
        if (n.count != 0) {
            ++s.leaves;
        } else if (n.first > i && std::size_t(n.first) + 1 < nodes.size() && d < 255) {
            depth[n.first] = depth[n.first + 1] = std::uint8_t(d + 1);
        } else {
            ordered = false;
        }
    }
    if (ordered) return s;
    s = TreeShape{};
    std::vector<std::pair<std::uint32_t, int>> stack{{0u, 1}};
    while (!stack.empty()) {
        auto [i, d] = stack.back();
        stack.pop_back();
        s.depth = std::max(s.depth, d);
        const Node& n = nodes[i];
        if (n.count != 0) {
            ++s.leaves;
        } else {
            stack.push_back({n.first, d + 1});
            stack.push_back({n.first + 1, d + 1});
        }
    }
    return s;
}

}  // namespace simdbvh::detail
