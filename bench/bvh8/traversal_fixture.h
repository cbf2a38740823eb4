#pragma once
// Shared by bench/bvh2 and bench/bvh8 traversal benchmarks: one scene, its
// BVH2, the BVH4, BVH8 and BVH16 collapsed from it (BVH8 and BVH16 also with
// quantized nodes), and the rays of each kind,
// built once per run (untimed).
// Scene: $SIMDBVH_BENCH_SCENE, default dragon when cached, else terrain.
// Rays per kind: $SIMDBVH_BENCH_RAYS (default 100000); primary_hd: the
// primary rays' camera at $SIMDBVH_BENCH_HD_SIDE squared pixels (default
// 1000 x 1000), in image order (the coherent input packets are for).
#include <iterator>
#include <string>
#include <vector>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/workloads/rays.h"

namespace bench {

struct TraversalScene {
    std::string name;
    simdbvh::Mesh mesh;
    simdbvh::Bvh2 bvh2;
    simdbvh::Bvh8 bvh8;         // SAH collapse (default options)
    simdbvh::Bvh8 bvh8_greedy;  // greedy collapse
    simdbvh::Bvh4 bvh4;         // SAH collapse of the same BVH2, 4 and 16 wide
    simdbvh::Bvh16 bvh16;
    simdbvh::Bvh8 bvh8q;  // bvh8 and bvh16 with quantized nodes (WideOptions::quantized_nodes)
    simdbvh::Bvh16 bvh16q;
    // The tree of width N (4, 8 or 16), for rows written once for every width.
    template <int N>
    const simdbvh::BvhN<N>& wide() const {
        if constexpr (N == 4) return bvh4;
        else if constexpr (N == 8) return bvh8;
        else return bvh16;
    }
    std::vector<simdbvh::Ray> rays[std::size(simdbvh::workloads::kRayKinds)];  // indexed by RayKind
    std::vector<simdbvh::Ray> primary_hd;
};

const TraversalScene& traversal_scene();

inline const std::vector<simdbvh::Ray>& rays_of(simdbvh::workloads::RayKind k) {
    return traversal_scene().rays[static_cast<int>(k)];
}

}  // namespace bench
