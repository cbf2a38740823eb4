#pragma once
// Axis-aligned bounding box (24 bytes) and its surface area.
#include <limits>

#include "simdbvh/kernels/vec.h"

namespace simdbvh {

struct Aabb {
    Vec3 lo{std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity(),
            std::numeric_limits<float>::infinity()};
    Vec3 hi{-std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
            -std::numeric_limits<float>::infinity()};

    static constexpr Aabb empty() { return {}; }
    constexpr void grow(Vec3 p) {
        lo = vmin(p, lo);
        hi = vmax(p, hi);
    }
    constexpr void grow(const Aabb& b) {
        lo = vmin(b.lo, lo);
        hi = vmax(b.hi, hi);
    }
    constexpr bool is_empty() const { return !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z); }
    constexpr Vec3 extent() const { return hi - lo; }
    constexpr Vec3 center() const { return (lo + hi) * 0.5f; }
    constexpr bool contains(const Aabb& b) const {
        return lo.x <= b.lo.x && lo.y <= b.lo.y && lo.z <= b.lo.z && hi.x >= b.hi.x && hi.y >= b.hi.y && hi.z >= b.hi.z;
    }
    constexpr int largest_axis() const {
        Vec3 e = extent();
        return e.x >= e.y && e.x >= e.z ? 0 : (e.y >= e.z ? 1 : 2);
    }
    // Half the surface area (the SAH only needs ratios); 0 for an empty box.
    // In double from double extents: finite for every finite box (a float
    // extent overflows past 3.4e38, a float area past 1.8e19 per side).
    constexpr double half_area() const {
        if (is_empty()) return 0.0;
        const double ex = double(hi.x) - double(lo.x), ey = double(hi.y) - double(lo.y),
                     ez = double(hi.z) - double(lo.z);
        return (ex * ey + ey * ez) + ez * ex;
    }
    // The same in float, as the builders computed it before: +inf (or NaN) once
    // the box passes about 1.8e19 per side. Builders use it only when the
    // whole tree's costs fit in float, so their trees keep the same bits.
    constexpr float half_area_float() const {
        if (is_empty()) return 0.0f;
        Vec3 e = extent();
        return e.x * e.y + e.y * e.z + e.z * e.x;
    }
};
static_assert(sizeof(Aabb) == 24);

}  // namespace simdbvh
