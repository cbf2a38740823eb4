#pragma once
// shapes.h's nearest_planes, four rays per vector: each lane runs
// nearest_plane's loop with plane_t's double arithmetic (shapes.cpp) on its
// own prepared ray, the same IEEE operations in the same order (the build has
// -ffp-contract=off), so the plane and the bits of t are nearest_plane's.
// Included only by the per-ISA translation units (src/avx2, src/avx512), whose
// flags make each vector of four doubles one ymm register.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>

#include "plane_batch.h"

namespace simdbvh::scene_accel {

template <class Tag>
void PlaneBatch<Tag>::nearest(std::span<const Ray> rays, std::span<const Plane> planes, bool any, int* plane,
                              float* t) {
    typedef double Double4 __attribute__((vector_size(32)));
    typedef std::int64_t Long4 __attribute__((vector_size(32)));
    typedef float Float4 __attribute__((vector_size(16)));
    typedef std::int32_t Int4 __attribute__((vector_size(16)));
    const std::int32_t none = std::int32_t(planes.size());
    const Double4 one = Double4{} + 1.0;
    for (std::size_t i = 0; i < rays.size(); i += 4) {
        const std::size_t g = std::min<std::size_t>(4, rays.size() - i);
        // The prepared rays' fields, lane l for ray i + l; a lane without a
        // valid ray keeps tmin > tmax, so no plane is in its range.
        alignas(32) double f[6][4] = {};
        alignas(16) float lim[2][4] = {{1, 1, 1, 1}, {0, 0, 0, 0}};
        int t_exp[4] = {};
        for (std::size_t l = 0; l < g; ++l) {
            const PreparedRay r = prepare_scaled(rays[i + l]);
            if (!r.valid) continue;
            f[0][l] = r.org.x, f[1][l] = r.org.y, f[2][l] = r.org.z;
            f[3][l] = r.dir.x, f[4][l] = r.dir.y, f[5][l] = r.dir.z;
            lim[0][l] = r.tmin, lim[1][l] = r.tmax;
            t_exp[l] = r.t_exp;
        }
        Double4 ox, oy, oz, dx, dy, dz;
        Float4 tmin, tmax;
        std::memcpy(&ox, f[0], sizeof ox), std::memcpy(&oy, f[1], sizeof oy), std::memcpy(&oz, f[2], sizeof oz);
        std::memcpy(&dx, f[3], sizeof dx), std::memcpy(&dy, f[4], sizeof dy), std::memcpy(&dz, f[5], sizeof dz);
        std::memcpy(&tmin, lim[0], sizeof tmin), std::memcpy(&tmax, lim[1], sizeof tmax);
        Int4 best = Int4{} + none;
        Float4 bt = Float4{} + std::numeric_limits<float>::infinity();
        for (std::int32_t k = 0; k < none; ++k) {
            const Plane& p = planes[std::size_t(k)];
            const double nx = p.normal.x, ny = p.normal.y, nz = p.normal.z;
            const Double4 dn = dx * nx + dy * ny + dz * nz;
            const Double4 num =
                (double(p.point.x) - ox) * nx + (double(p.point.y) - oy) * ny + (double(p.point.z) - oz) * nz;
            const Long4 parallel = dn == 0.0;
            const Float4 tv = __builtin_convertvector(num / (parallel ? one : dn), Float4);
            // In range, and nearer than the best so far (ties: the lower
            // plane; any: the first plane hit).
            const Int4 nearer = any ? Int4{} : Int4(tv < bt);
            const Int4 take =
                ~__builtin_convertvector(parallel, Int4) & (tv >= tmin) & (tv <= tmax) & ((best == none) | nearer);
            best = take ? Int4{} + k : best;
            bt = take ? tv : bt;
        }
        alignas(16) std::int32_t b[4];
        alignas(16) float bv[4];
        std::memcpy(b, &best, sizeof b), std::memcpy(bv, &bt, sizeof bv);
        for (std::size_t l = 0; l < g; ++l) {
            plane[i + l] = b[l] == none ? -1 : b[l];
            t[i + l] = b[l] == none ? 0.0f : to_caller_t(t_exp[l], bv[l]);
        }
    }
}

}  // namespace simdbvh::scene_accel

// The one line of each per-ISA translation unit: its tag and its instantiation.
#define SIMDBVH_PLANE_BATCH_INSTANTIATE(isa)                      \
    namespace simdbvh::scene_accel {                              \
    namespace isa {                                               \
    struct PlaneTag {};                                           \
    }                                                             \
    template struct PlaneBatch<isa::PlaneTag>;                    \
    }
