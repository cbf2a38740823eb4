// An outside project built against an installed simdbvh, with only the
// README's include. It checks that
//  - simdbvh::Error is declared by that include and thrown for a bad mesh;
//  - the inline kernels of the public headers, compiled here (the consumer is
//    built with -march=haswell -ffp-contract=fast, see run.sh), give the same
//    bits as the library's compiled paths: the exported target must carry
//    -ffp-contract=off, or the shear and edge functions contract into FMAs;
//  - a BVH8 answers like the brute force.
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "simdbvh/simdbvh.h"

namespace {

std::uint64_t state = 0x9E3779B97F4A7C15ull;
float uniform() {  // splitmix64 -> [0, 1)
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return float(z >> 40) * 0x1p-24f;
}
float signed_uniform() { return 2.0f * uniform() - 1.0f; }

}  // namespace

int main() {
    // 1. The documented exception is catchable with this one include.
    simdbvh::Mesh bad;
    bad.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    bad.triangles = {{0, 1, 7}};
    try {
        (void)simdbvh::Bvh8::build(bad);
        std::printf("an out-of-range index was accepted\n");
        return 1;
    } catch (const simdbvh::Error& e) {
        std::printf("caught simdbvh::Error: %s\n", e.what());
    }

    // 2. 2,000 random triangles, 20,000 random rays from a shell around them.
    simdbvh::Mesh m;
    for (int i = 0; i < 2000; ++i) {
        const simdbvh::Vec3 c{signed_uniform(), signed_uniform(), signed_uniform()};
        const auto idx = std::uint32_t(m.positions.size());
        for (int k = 0; k < 3; ++k)
            m.positions.push_back(
                {c.x + 0.3f * signed_uniform(), c.y + 0.3f * signed_uniform(), c.z + 0.3f * signed_uniform()});
        m.triangles.push_back({idx, idx + 1, idx + 2});
    }
    std::vector<simdbvh::Ray> rays(20000);
    for (simdbvh::Ray& r : rays) {
        r.org = {3.0f * signed_uniform(), 3.0f * signed_uniform(), 3.0f * signed_uniform()};
        r.dir = {signed_uniform() - 0.3f * r.org.x, signed_uniform() - 0.3f * r.org.y,
                 signed_uniform() - 0.3f * r.org.z};
    }

    const simdbvh::Bvh8 bvh = simdbvh::Bvh8::build(m);
    std::vector<simdbvh::Hit> wide(rays.size());
    simdbvh::intersect(bvh, rays, wide);

    std::size_t hits = 0, inline_diff = 0, brute_diff = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const simdbvh::Hit brute = simdbvh::brute_force_intersect(m, rays[i]);  // compiled in the library
        // The same search with the header's inline watertight test, compiled here.
        const simdbvh::PreparedRay p = simdbvh::prepare(rays[i]);
        simdbvh::Hit here;
        for (std::uint32_t t = 0; t < m.triangles.size(); ++t) {
            float tt, u, v;
            if (simdbvh::intersect_watertight(p, m.vertex(t, 0), m.vertex(t, 1), m.vertex(t, 2), here.t, &tt, &u, &v) &&
                simdbvh::closer(tt, t, here))
                here = {tt, u, v, t};
        }
        hits += brute.hit();
        inline_diff += !(here == brute);
        brute_diff += !(wide[i] == brute);
    }
    std::printf("%zu rays, %zu hits; inline kernel differs on %zu, BVH8 differs on %zu; isa %s\n", rays.size(), hits,
                inline_diff, brute_diff, std::string(simdbvh::name(simdbvh::active_isa())).c_str());
    if (hits < rays.size() / 4 || inline_diff != 0 || brute_diff != 0) return 1;
    std::printf("consumer ok\n");
    return 0;
}
