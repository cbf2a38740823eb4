// Edge statistics of a mesh after welding equal vertex coordinates (see
// MeshClosure in simdbvh/query/inside.h).
#include <algorithm>
#include <cstring>
#include <numeric>
#include <vector>

#include "simdbvh/query/inside.h"

namespace simdbvh {

MeshClosure mesh_closure(const Mesh& mesh) {
    validate(mesh);
    // Weld: vertices with bit-equal coordinates (after +0 == -0) get one id.
    const std::size_t nv = mesh.positions.size();
    std::vector<std::uint32_t> order(nv);
    std::iota(order.begin(), order.end(), 0u);
    auto key = [&](std::uint32_t i) {
        const Vec3& p = mesh.positions[i];
        return std::array<float, 3>{p.x + 0.0f, p.y + 0.0f, p.z + 0.0f};
    };
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return key(a) < key(b); });
    std::vector<std::uint32_t> weld(nv);
    for (std::size_t k = 0; k < nv; ++k)
        weld[order[k]] = (k > 0 && key(order[k]) == key(order[k - 1])) ? weld[order[k - 1]] : order[k];
    // Directed edges (lo, hi, forward?) of the non-degenerate triangles.
    struct Edge {
        std::uint32_t lo, hi;
        bool forward;
        bool operator<(const Edge& o) const {
            return lo != o.lo ? lo < o.lo : (hi != o.hi ? hi < o.hi : forward < o.forward);
        }
    };
    std::vector<Edge> edges;
    edges.reserve(mesh.triangles.size() * 3);
    for (const Triangle& t : mesh.triangles) {
        const std::uint32_t v[3] = {weld[t[0]], weld[t[1]], weld[t[2]]};
        if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) continue;
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = v[k], b = v[(k + 1) % 3];
            edges.push_back(a < b ? Edge{a, b, true} : Edge{b, a, false});
        }
    }
    std::sort(edges.begin(), edges.end());
    MeshClosure c;
    for (std::size_t i = 0; i < edges.size();) {
        std::size_t j = i, fwd = 0;
        while (j < edges.size() && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi) fwd += edges[j++].forward;
        const std::size_t uses = j - i;
        c.edges++;
        if (uses == 1) c.boundary_edges++;
        else if (uses > 2) c.nonmanifold_edges++;
        else if (fwd != 1) c.misoriented_edges++;
        i = j;
    }
    return c;
}

}  // namespace simdbvh
