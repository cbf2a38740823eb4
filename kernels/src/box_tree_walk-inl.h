#pragma once
// Internal: the walk of batch.h's collect_box8_tree, written once for every
// ISA. `Test` is the node test of one ISA: ray(r) makes its per-ray state and
// mask(state, n, e) tests the 8 lanes of node n, writing their entries to e
// (in the ray's prepared parameter) and returning the lanes hit. The tree is
// checked before (batch.cpp): every inner child comes after its parent and is
// reached from one lane only, so a ray pushes each node at most once and the
// stack holds at most nodes.size() entries. No intrinsics here.
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "simdbvh/kernels/batch.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/kernels/ray.h"

namespace simdbvh::kernels::detail {

template <class Test>
inline void walk_box_tree(std::span<const Ray> rays, std::span<const std::uint8_t> live, std::size_t nodes,
                          std::span<const std::uint32_t> children, std::vector<std::pair<float, std::uint32_t>>& out,
                          std::uint32_t* first, const Test& test) {
    std::vector<std::uint32_t> stack(nodes);
    constexpr std::size_t kMaxResults = 0xFFFFFFFFu;  // first[] holds 32-bit offsets
    for (std::size_t i = 0; i < rays.size(); ++i) {
        if (out.size() > kMaxResults) throw Error("simdbvh: box tree: more than 2^32 - 1 results");
        first[i] = std::uint32_t(out.size());
        if (nodes == 0 || (!live.empty() && live[i] == 0)) continue;
        const PreparedRay r = prepare(rays[i]);
        if (!r.valid) continue;
        const auto state = test.ray(r);
        std::size_t sp = 0;
        stack[sp++] = 0;
        while (sp > 0) {
            const std::uint32_t n = stack[--sp];
            alignas(64) float e[8];
            for (std::uint32_t m = test.mask(state, n, e); m != 0; m &= m - 1) {
                const int j = __builtin_ctz(m);
                const std::uint32_t c = children[8 * std::size_t(n) + std::size_t(j)];
                if (c == kBoxTreeEmpty) continue;
                if ((c & kBoxTreeLeaf) != 0) out.push_back({to_caller_t(r, e[j]), c & ~kBoxTreeLeaf});
                else stack[sp++] = c;
            }
        }
    }
    if (out.size() > kMaxResults) throw Error("simdbvh: box tree: more than 2^32 - 1 results");
    first[rays.size()] = std::uint32_t(out.size());
}

}  // namespace simdbvh::kernels::detail
