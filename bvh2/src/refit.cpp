// Bvh2::refit: new vertex positions, the same topology. Leaves are
// re-gathered and re-bounded in parallel, then the inner nodes are bounded
// in reverse index order (the builders put children after their parent).
#include <string>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/platform/parallel.h"

namespace simdbvh {

namespace {

Aabb triangle_box(const TriangleVerts& t) {
    Aabb b;
    b.grow(t.v0);
    b.grow(t.v1);
    b.grow(t.v2);
    return b;
}

}  // namespace

void Bvh2::refit(const Mesh& mesh, int threads) {
    if (mesh.size() != stats_.triangles || prim_ids_.size() != stats_.triangles)
        throw Error("BVH2 refit: the mesh has " + std::to_string(mesh.size()) + " triangles, the tree " +
                    std::to_string(stats_.triangles));
    validate(mesh);
    // Every check before the first write: on error the tree is unchanged.
    const std::size_t n = nodes_.size();
    for (std::size_t i = 0; i < n; ++i) {
        const Node2& nd = nodes_[i];
        const bool ok = nd.is_leaf() ? std::size_t(nd.first) + nd.count <= prim_ids_.size()
                                     : nd.first > i && std::size_t(nd.first) + 1 < n;
        if (!ok) throw Error("BVH2 refit: node " + std::to_string(i) + " is not in builder order");
    }
    ParallelOptions po;
    po.grain = 1024;
    po.pin = false;
    parallel_for(
        n, threads,
        [&](std::size_t b, std::size_t e) {
            for (std::size_t i = b; i < e; ++i) {
                Node2& nd = nodes_[i];
                if (!nd.is_leaf()) continue;
                Aabb box;
                for (std::uint32_t k = nd.first; k < nd.first + nd.count; ++k) {
                    const std::uint32_t p = prim_ids_[k];
                    tris_[k] = {mesh.vertex(p, 0), mesh.vertex(p, 1), mesh.vertex(p, 2)};
                    box.grow(triangle_box(tris_[k]));
                }
                nd.box = box;
            }
        },
        po);
    for (std::size_t i = n; i-- > 0;) {
        Node2& nd = nodes_[i];
        if (nd.is_leaf()) continue;
        Aabb box = nodes_[nd.first].box;
        box.grow(nodes_[nd.first + 1].box);
        nd.box = box;
    }
    stats_.sah_cost = sah_cost(nodes_, prim_ids_.size(), opts_.traversal_cost, opts_.intersection_cost);
}

}  // namespace simdbvh
