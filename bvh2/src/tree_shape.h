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

template <class Node>
TreeShape tree_shape(const std::vector<Node>& nodes) {
    TreeShape s;
    if (nodes.empty()) return s;
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
