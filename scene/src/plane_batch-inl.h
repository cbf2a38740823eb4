#pragma once
// shapes.h's nearest_planes, four rays per vector: each lane runs
// nearest_plane's loop with plane_t's double arithmetic (shapes.cpp) on its
// own prepared ray, the same IEEE operations in the same order (the build has
// -ffp-contract=off), so the plane and the bits of t are nearest_plane's.
// Included only by the per-ISA translation units (src/avx2, src/avx512), whose
// flags make each vector of four doubles one ymm register.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>

#include "plane_batch.h"

namespace simdbvh::scene::detail {

namespace plane_batch_detail {

typedef double Double4 __attribute__((vector_size(32)));
typedef float Float4 __attribute__((vector_size(16)));
typedef std::int32_t Int4 __attribute__((vector_size(16)));

// Rays r[0 .. 4) transposed into lanes, when prepare_scaled() would leave
// each as given (valid, its largest direction component in [kRescaleBelow,
// kRescaleAbove], no subnormal component to flush): then its org, dir, tmin
// and tmax are the prepared ray's and t_exp is 0, the values the per-ray
// loop below fills in. Else false (that loop runs). A Ray is (org, tmin),
// (dir, tmax): two 16-byte rows per ray. A template on the ISA's tag, so no
// copy compiled with one ISA's flags can stand in for another's.
template <class Tag>
inline __attribute__((always_inline)) bool as_given(const Ray* r, Double4& ox, Double4& oy, Double4& oz, Double4& dx,
                                                    Double4& dy, Double4& dz, Float4& tmin, Float4& tmax) {
    static_assert(sizeof(Ray) == 32 && offsetof(Ray, tmin) == 12 && offsetof(Ray, dir) == 16 &&
                  offsetof(Ray, tmax) == 28);
    Float4 a[4], b[4];
    for (int l = 0; l < 4; ++l) {
        std::memcpy(&a[l], reinterpret_cast<const char*>(r + l), 16);
        std::memcpy(&b[l], reinterpret_cast<const char*>(r + l) + 16, 16);
    }
    auto transpose = [](const Float4* v, Float4& x, Float4& y, Float4& z, Float4& w) {
        const Float4 t0 = __builtin_shufflevector(v[0], v[1], 0, 4, 1, 5);
        const Float4 t1 = __builtin_shufflevector(v[2], v[3], 0, 4, 1, 5);
        const Float4 t2 = __builtin_shufflevector(v[0], v[1], 2, 6, 3, 7);
        const Float4 t3 = __builtin_shufflevector(v[2], v[3], 2, 6, 3, 7);
        x = __builtin_shufflevector(t0, t1, 0, 1, 4, 5);
        y = __builtin_shufflevector(t0, t1, 2, 3, 6, 7);
        z = __builtin_shufflevector(t2, t3, 0, 1, 4, 5);
        w = __builtin_shufflevector(t2, t3, 2, 3, 6, 7);
    };
    Float4 px, py, pz, qx, qy, qz;
    transpose(a, px, py, pz, tmin);
    transpose(b, qx, qy, qz, tmax);
    auto abs4 = [](Float4 v) { return Float4(Int4(v) & std::numeric_limits<std::int32_t>::max()); };
    const float big = std::numeric_limits<float>::max(), tiny = std::numeric_limits<float>::min();
    const Float4 ax = abs4(qx), ay = abs4(qy), az = abs4(qz);
    const Float4 m = ax > ay ? (ax > az ? ax : az) : (ay > az ? ay : az);        // NaN: fails below
    const Int4 ok = (abs4(px) <= big) & (abs4(py) <= big) & (abs4(pz) <= big) &  // finite origin
                    (m >= kRescaleBelow) & (m <= kRescaleAbove) &                // no rescale (and finite, not 0)
                    (ax <= big) & (ay <= big) & (az <= big) &                    // a finite direction
                    ((ax >= tiny) | (qx == 0.0f)) & ((ay >= tiny) | (qy == 0.0f)) & ((az >= tiny) | (qz == 0.0f)) &
                    (tmin <= tmax);  // false for a NaN
    if ((ok[0] & ok[1] & ok[2] & ok[3]) == 0) return false;
    ox = __builtin_convertvector(px, Double4), oy = __builtin_convertvector(py, Double4);
    oz = __builtin_convertvector(pz, Double4);
    dx = __builtin_convertvector(qx, Double4), dy = __builtin_convertvector(qy, Double4);
    dz = __builtin_convertvector(qz, Double4);
    return true;
}

}  // namespace plane_batch_detail

template <class Tag>
void PlaneBatch<Tag>::nearest(std::span<const Ray> rays, std::span<const Plane> planes, bool any, int* plane,
                              float* t) {
    using plane_batch_detail::as_given;
    using plane_batch_detail::Double4;
    using plane_batch_detail::Float4;
    using plane_batch_detail::Int4;
    typedef std::int64_t Long4 __attribute__((vector_size(32)));
    const std::int32_t none = std::int32_t(planes.size());
    const Double4 one = Double4{} + 1.0;
    for (std::size_t i = 0; i < rays.size(); i += 4) {
        const std::size_t g = std::min<std::size_t>(4, rays.size() - i);
        Double4 ox, oy, oz, dx, dy, dz;
        Float4 tmin, tmax;
        int t_exp[4] = {};
        if (g == 4 && as_given<Tag>(rays.data() + i, ox, oy, oz, dx, dy, dz, tmin, tmax)) {
            // Four rays prepare_scaled() leaves as they are (most rays).
        } else {
            // The prepared rays' fields, lane l for ray i + l; a lane without a
            // valid ray keeps tmin > tmax, so no plane is in its range.
            alignas(32) double f[6][4] = {};
            alignas(16) float lim[2][4] = {{1, 1, 1, 1}, {0, 0, 0, 0}};
            for (std::size_t l = 0; l < g; ++l) {
                const PreparedRay r = prepare_scaled(rays[i + l]);
                if (!r.valid) continue;
                f[0][l] = r.org.x, f[1][l] = r.org.y, f[2][l] = r.org.z;
                f[3][l] = r.dir.x, f[4][l] = r.dir.y, f[5][l] = r.dir.z;
                lim[0][l] = r.tmin, lim[1][l] = r.tmax;
                t_exp[l] = r.t_exp;
            }
            std::memcpy(&ox, f[0], sizeof ox), std::memcpy(&oy, f[1], sizeof oy), std::memcpy(&oz, f[2], sizeof oz);
            std::memcpy(&dx, f[3], sizeof dx), std::memcpy(&dy, f[4], sizeof dy), std::memcpy(&dz, f[5], sizeof dz);
            std::memcpy(&tmin, lim[0], sizeof tmin), std::memcpy(&tmax, lim[1], sizeof tmax);
        }
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
            // Any hit: a lane keeps its first plane, so once every lane has
            // one the later planes change nothing.
            if (any) {
                const Int4 open = best == none;
                if ((open[0] | open[1] | open[2] | open[3]) == 0) break;
            }
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

}  // namespace simdbvh::scene::detail

// The one line of each per-ISA translation unit: its tag and its instantiation.
#define SIMDBVH_PLANE_BATCH_INSTANTIATE(isa)   \
    namespace simdbvh::scene::detail {         \
    namespace isa {                            \
    struct PlaneTag {};                        \
    }                                          \
    template struct PlaneBatch<isa::PlaneTag>; \
    }
