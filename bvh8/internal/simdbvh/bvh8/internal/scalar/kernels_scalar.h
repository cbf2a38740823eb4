#pragma once
// Internal: the scalar kernels behind traverse-inl.h's K interface (baseline
// x86-64, no AVX, no xsimd): the scalar reference tests (box.h, triangle.h),
// one lane at a time. Include only from src/scalar translation units (here
// and scene/src/scalar).
#include "simdbvh/kernels/box.h"
#include "simdbvh/kernels/triangle.h"
#include "simdbvh/bvh8/node.h"
#include "simdbvh/bvh8/qnode.h"

namespace simdbvh::bvh8 {

namespace scalar {

struct Kernels {
    using RayData = PreparedRay;
    static constexpr bool kStreams = false;  // no stream path (stream-inl.h) for the baseline ISA
    static void pack(RayData& d, const PreparedRay& r, const Ray&) { d = r; }
    // Rays [0, g) prepared and tested against the tree's bounds, one at a time
    // (the SIMD kernels' prepare8 gives the same bits).
    static std::uint32_t prepare8(const Ray* rays, std::size_t g, const Aabb* root, PreparedRay* out,
                                  std::uint32_t* valid) {
        std::uint32_t hit = 0, v = 0;
        for (std::size_t l = 0; l < g; ++l) {
            out[l] = prepare(rays[l]);
            v |= std::uint32_t(out[l].valid) << l;
            float entry;
            if (root && out[l].valid && intersect_box(out[l], *root, out[l].tmax, &entry)) hit |= 1u << l;
        }
        *valid = root ? v : 0;
        return hit;
    }
    template <int N>
    static std::uint32_t box(const PreparedRay& r, const BoxN<N>& b, float tmax, float* entries) {
        std::uint32_t m = 0;
        for (int i = 0; i < N; ++i) m |= std::uint32_t(intersect_box(r, b.get(i), tmax, &entries[i])) << i;
        return m;
    }
    template <int N>
    static std::uint32_t box(const PreparedRay& r, const QBoxN<N>& b, float tmax, float* entries) {
        std::uint32_t m = 0;
        for (int i = 0; i < N; ++i)
            if (b.valid >> i & 1u) m |= std::uint32_t(intersect_box(r, b.get(i), tmax, &entries[i])) << i;
        return m;
    }
    // Lanes in order with a shrinking tmax: the same result as the 8-wide
    // kernels' lane minimum under closer().
    template <TriangleTest kTest>
    static void closest(const PreparedRay& r, const Tri8& b, Hit& best) {
        for (int i = 0; i < kBlockWidth; ++i) {
            float t, u, v;
            if (intersect_triangle<kTest>(r, b.v0(i), b.v1(i), b.v2(i), best.t, &t, &u, &v) &&
                closer(t, b.prim[i], best))
                best = Hit{t, u, v, b.prim[i]};
        }
    }
    template <TriangleTest kTest>
    static bool any(const PreparedRay& r, const Tri8& b, float tmax, Hit& hit) {
        for (int i = 0; i < kBlockWidth; ++i) {
            float t, u, v;
            if (intersect_triangle<kTest>(r, b.v0(i), b.v1(i), b.v2(i), tmax, &t, &u, &v)) {
                hit = Hit{t, u, v, b.prim[i]};
                return true;
            }
        }
        return false;
    }
};

}  // namespace scalar

}  // namespace simdbvh::bvh8
