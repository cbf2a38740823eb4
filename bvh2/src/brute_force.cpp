// The O(rays x triangles) reference: same triangle test, same tie rule.
#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/kernels/error.h"

namespace simdbvh {

namespace {

template <TriangleTest kTest, bool kAnyHit>
Hit brute(const Mesh& mesh, const Ray& ray) {
    const PreparedRay r = prepare(ray);
    Hit best;
    if (!r.valid) return best;
    best.t = r.tmax;
    const std::size_t nv = mesh.positions.size();
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
        const Triangle& tri = mesh.triangles[i];
        if (tri[0] >= nv || tri[1] >= nv || tri[2] >= nv) continue;  // invalid: never hit
        float t, u, v;
        if (intersect_triangle<kTest>(r, mesh.positions[tri[0]], mesh.positions[tri[1]], mesh.positions[tri[2]], best.t,
                                      &t, &u, &v)) {
            if (kAnyHit) return to_caller(r, Hit{t, u, v, std::uint32_t(i)});
            if (closer(t, std::uint32_t(i), best)) best = {t, u, v, std::uint32_t(i)};
        }
    }
    return best.hit() ? to_caller(r, best) : Hit{};
}

}  // namespace

Hit brute_force_intersect(const Mesh& mesh, const Ray& ray, TriangleTest test) {
    return test == TriangleTest::watertight ? brute<TriangleTest::watertight, false>(mesh, ray)
                                            : brute<TriangleTest::moller, false>(mesh, ray);
}
Hit brute_force_occluded(const Mesh& mesh, const Ray& ray, TriangleTest test) {
    return test == TriangleTest::watertight ? brute<TriangleTest::watertight, true>(mesh, ray)
                                            : brute<TriangleTest::moller, true>(mesh, ray);
}
void brute_force_intersect(const Mesh& mesh, std::span<const Ray> rays, std::span<Hit> hits, TriangleTest test) {
    simdbvh::detail::check_size(hits.size(), rays.size(), "hits");
    for (std::size_t i = 0; i < rays.size(); ++i) hits[i] = brute_force_intersect(mesh, rays[i], test);
}

}  // namespace simdbvh
