#pragma once
// The batched loops of kernels/batch.h, written once for any 8-wide Arch and
// instantiated by src/avx2/kernels_avx2.cpp and src/avx512/kernels_avx512.cpp.
#include <limits>

#include "simd/box8-inl.h"
#include "simd/dispatch.h"
#include "simd/tri8-inl.h"

namespace simdbvh::simd {

template <class Arch>
struct BatchLoops {
    static SIMDBVH_FORCE_INLINE void box8(std::span<const Ray> rays, const Box8& boxes, std::uint8_t* masks,
                                          float* entries) {
        for (std::size_t i = 0; i < rays.size(); ++i) {
            const PreparedRay r = prepare(rays[i]);
            if (!r.valid) {
                masks[i] = 0;
                for (int j = 0; j < 8; ++j) entries[8 * i + j] = std::numeric_limits<float>::infinity();
                continue;
            }
            const RayPack<Arch> p = pack_ray<Arch>(r);
            masks[i] = static_cast<std::uint8_t>(intersect_box8<Arch>(p, boxes, r.tmax, entries + 8 * i));
            if (r.t_exp != 0)
                for (int j = 0; j < 8; ++j) entries[8 * i + j] = to_caller_t(r, entries[8 * i + j]);
        }
    }

    static SIMDBVH_FORCE_INLINE std::uint64_t count_box8(std::span<const Ray> rays, std::span<const Box8> blocks) {
        std::uint64_t n = 0;
        for (const Ray& ray : rays) {
            const PreparedRay r = prepare(ray);
            if (!r.valid) continue;
            const RayPack<Arch> p = pack_ray<Arch>(r);
            const Batch<Arch> tmax(r.tmax);
            for (const Box8& b : blocks) {
                Batch<Arch> tn;
                n += static_cast<std::uint64_t>(__builtin_popcount(intersect_box8<Arch>(p, b, tmax, tn)));
            }
        }
        return n;
    }

    template <TriangleTest kTest>
    static SIMDBVH_FORCE_INLINE void closest(std::span<const Ray> rays, std::span<const Tri8> blocks, Hit* hits) {
        for (std::size_t i = 0; i < rays.size(); ++i) {
            const PreparedRay r = prepare(rays[i]);
            Hit best;
            if (r.valid) {
                const RayPack<Arch> p = pack_ray<Arch>(r);
                best.t = r.tmax;
                for (const Tri8& b : blocks) intersect_tri8<Arch, kTest>(p, b, best);
                if (!best.hit()) best = Hit{};
            }
            hits[i] = to_caller(r, best);
        }
    }

    template <TriangleTest kTest>
    static SIMDBVH_FORCE_INLINE void any(std::span<const Ray> rays, std::span<const Tri8> blocks,
                                         std::uint8_t* occluded, Hit* first_hits) {
        for (std::size_t i = 0; i < rays.size(); ++i) {
            const PreparedRay r = prepare(rays[i]);
            Hit h;
            bool found = false;
            if (r.valid) {
                const RayPack<Arch> p = pack_ray<Arch>(r);
                for (const Tri8& b : blocks)
                    if ((found = occluded_tri8<Arch, kTest>(p, b, r.tmax, h))) break;
            }
            occluded[i] = found ? 1 : 0;
            if (first_hits) first_hits[i] = found ? to_caller(r, h) : Hit{};
        }
    }
};

}  // namespace simdbvh::simd
