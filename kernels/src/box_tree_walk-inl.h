#pragma once
// Internal: the walk of batch.h's collect_box8_tree, written once for every
// ISA. `Test` is the node test of one ISA: ray(r) makes its per-ray state and
// mask(state, n, e) tests the 8 lanes of node n, writing their entries to e
// (in the ray's prepared parameter) and returning the lanes hit. The tree is
// checked before (batch.cpp): every inner child comes after its parent and is
// reached from one lane only, so a ray pushes each node at most once (the
// stack holds nodes.size() entries) and reaches at most `leaf_lanes` leaves.
// Nothing here allocates or throws (the per-ISA objects must not define the
// library's shared inline functions, tests/kernels/check_isa_objects.cmake):
// the walk stops before a ray that might not fit the output, and batch.cpp
// grows it and calls again. No intrinsics here.
#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>

#include "simdbvh/kernels/batch.h"
#include "simdbvh/kernels/ray.h"

namespace simdbvh::kernels::detail {

struct TreeWalk {
    std::size_t rays_done = 0;  // rays [0, rays_done) have their results and first[]
    std::size_t used = 0;       // entries of `out` in use
};

template <class Test>
__attribute__((always_inline)) inline TreeWalk walk_box_tree(std::span<const Ray> rays,
                                                             std::span<const std::uint8_t> live, bool has_nodes,
                                                             std::span<const std::uint32_t> children,
                                                             std::size_t leaf_lanes, std::uint32_t* stack,
                                                             std::pair<float, std::uint32_t>* out, std::size_t used,
                                                             std::size_t cap, std::uint32_t* first, const Test& test) {
    std::size_t i = 0;
    for (; i < rays.size(); ++i) {
        if (cap - used < leaf_lanes) break;
        first[i] = std::uint32_t(used);
        if (!has_nodes || (!live.empty() && live[i] == 0)) continue;
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
                if ((c & kBoxTreeLeaf) != 0) out[used++] = {to_caller_t(r, e[j]), c & ~kBoxTreeLeaf};
                else stack[sp++] = c;
            }
        }
    }
    return {i, used};
}

}  // namespace simdbvh::kernels::detail
