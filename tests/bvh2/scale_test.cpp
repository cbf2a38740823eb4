// Scale invariance: multiplying mesh and ray origins by a power of two (exact
// in float) gives the same triangles and u, v, and t scaled exactly. No
// epsilon in the library depends on the scene's units.
#include <gtest/gtest.h>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/workloads/rays.h"
#include "simdbvh/workloads/scenes.h"

namespace simdbvh {
namespace {

Mesh scaled(Mesh m, float s) {
    for (Vec3& p : m.positions) p = p * s;
    return m;
}

TEST(Scale, PowerOfTwoScalingIsExact) {
    for (const char* name : {"dragon-res4", "icosphere-5"}) {
        if (std::string(name).rfind("dragon", 0) == 0 && !workloads::is_cached(name)) {
            std::cout << "[ SKIPPED ] " << name << " not cached (run scripts/fetch_scenes.sh)\n";
            continue;
        }
        const Mesh base = workloads::load_scene(name);
        const auto rays = workloads::generate_rays(base, workloads::RayKind::incoherent, 4000, 3);
        const Bvh2 bvh = Bvh2::build(base);
        std::vector<Hit> want(rays.size());
        intersect(bvh, rays, want);
        std::size_t hits = 0;
        for (const Hit& h : want) hits += h.hit();
        ASSERT_GT(hits, rays.size() / 10);
        for (float s : {0x1p-10f, 0x1p10f}) {
            const Mesh m = scaled(base, s);
            std::vector<Ray> r2 = rays;
            for (Ray& r : r2) r.org = r.org * s;  // direction unchanged: t scales by s
            const Bvh2 b2 = Bvh2::build(m);
            std::vector<Hit> got(r2.size());
            intersect(b2, r2, got);
            for (std::size_t i = 0; i < rays.size(); ++i) {
                ASSERT_EQ(got[i].prim, want[i].prim) << name << " scale " << s << " ray " << i;
                if (!want[i].hit()) continue;
                ASSERT_EQ(got[i].t, want[i].t * s) << name << " ray " << i;
                ASSERT_EQ(got[i].u, want[i].u) << name << " ray " << i;
                ASSERT_EQ(got[i].v, want[i].v) << name << " ray " << i;
            }
        }
    }
}

}  // namespace
}  // namespace simdbvh
