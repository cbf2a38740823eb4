// Builds a BVH over two triangles through the installed package and checks hits.
#include <cmath>
#include <cstdio>
#include <string>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/kernels/isa.h"

int main() {
    simdbvh::Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 2}, {1, 0, 2}, {0, 1, 2}};
    m.triangles = {{0, 1, 2}, {3, 4, 5}};
    const simdbvh::Bvh2 bvh = simdbvh::Bvh2::build(m);
    const simdbvh::Ray ray{{0.2f, 0.2f, 5.0f}, 0.0f, {0.0f, 0.0f, -1.0f}, 100.0f};
    const simdbvh::Hit h = simdbvh::intersect(bvh, ray);
    if (h.prim != 1 || std::fabs(h.t - 3.0f) > 1e-5f) {  // the nearer triangle, 3 units away
        std::printf("unexpected hit: prim %u t %g\n", h.prim, h.t);
        return 1;
    }
    std::printf("consumer ok: prim %u t %g isa %s\n", h.prim, h.t, std::string(simdbvh::name(simdbvh::active_isa())).c_str());
    return 0;
}
