#pragma once
// Every crossing along a ray, each counted once: all hits in [tmin, tmax]
// sorted by (t, prim), and the signed crossing count (winding number of the
// origin for a closed mesh). The triangle test is the watertight one (Woop et
// al. 2013) on the sheared vertices, which every triangle sharing a vertex sees
// identically; where the ray passes exactly through an edge or a vertex (an
// edge function is exactly 0, decided in double), a top-left rule in the
// sheared plane gives the crossing to exactly one of the triangles on either
// side (docs/exact_crossings.md). Closest hit keeps its own rule (ties at equal
// t to the lower id), so at a shared edge it may name the other triangle.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/kernels/mesh.h"

namespace simdbvh {

struct Crossing {
    float t = 0, u = 0, v = 0;  // as Hit (t in the caller's units)
    std::uint32_t prim = kInvalidPrim;
    std::int32_t facing = 0;  // +1: the triangle's normal points along the ray (leaving), -1 entering
};

struct AllHits {
    std::vector<Crossing> hits;  // sorted by (t, prim), at most `cap`
    std::uint64_t dropped = 0;   // crossings beyond the cap (the farthest ones)
};

struct CrossingCount {
    std::int32_t winding = 0;  // sum of facing over the crossings in [tmin, tmax]
    std::uint32_t crossings = 0;
};

AllHits intersect_all(const Bvh2& bvh, const Ray& ray, std::size_t cap = 1024);
CrossingCount count_crossings(const Bvh2& bvh, const Ray& ray);
void count_crossings(const Bvh2& bvh, std::span<const Ray> rays, std::span<CrossingCount> out, int threads = 1);

// O(triangles) per ray, the same test and rule.
AllHits brute_force_intersect_all(const Mesh& mesh, const Ray& ray, std::size_t cap = 1024);
CrossingCount brute_force_count_crossings(const Mesh& mesh, const Ray& ray);

}  // namespace simdbvh
