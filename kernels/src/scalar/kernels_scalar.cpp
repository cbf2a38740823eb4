// Scalar kernels: plain loops over the reference functions of box.h and
// triangle.h, compiled for baseline x86-64 (no AVX; checked by a ctest).
#if defined(__AVX__)
#error "src/scalar/ must be compiled without AVX flags"
#endif
#include <limits>

#include "simd/dispatch.h"
#include "simdbvh/kernels/box.h"

namespace simdbvh::kernels {

namespace simd::detail {
// Declared in simd/tri8-inl.h: the exact path for SIMD lanes with a zero edge function.
bool watertight_exact(const PreparedRay& r, const Tri8& b, int lane, float tmax, float* t, float* u, float* v) {
    return intersect_watertight(r, b.v0(lane), b.v1(lane), b.v2(lane), tmax, t, u, v);
}
// Declared in simd/tri8-inl.h: the side of the origin of a lane whose t lies in the band of 0.
bool plane_in_front(float ox, float oy, float oz, float dx, float dy, float dz, const Tri8& b, int lane) {
    return simdbvh::detail::plane_t({ox, oy, oz}, {dx, dy, dz}, b.v0(lane), b.v1(lane), b.v2(lane)) >= 0.0;
}
}  // namespace simd::detail

// Single-primitive forms (scalar only), declared in batch.h.
void intersect_box1(std::span<const Ray> rays, std::span<const Aabb> boxes, std::span<std::uint8_t> hits,
                    std::span<float> entries) {
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const PreparedRay r = prepare(rays[i]);
        float e = std::numeric_limits<float>::infinity();
        const bool h = r.valid && intersect_box(r, boxes[i], r.tmax, &e);
        hits[i] = h ? 1 : 0;
        entries[i] = r.valid ? to_caller_t(r, e) : std::numeric_limits<float>::infinity();
    }
}

void intersect_tri1(std::span<const Ray> rays, std::span<const Tri1> tris, TriangleTest test, std::span<Hit> hits) {
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const PreparedRay r = prepare(rays[i]);
        const Tri1& tri = tris[i];
        Hit h;
        float t, u, v;
        if (r.valid &&
            (test == TriangleTest::watertight ? intersect_watertight(r, tri.v0, tri.v1, tri.v2, r.tmax, &t, &u, &v)
                                              : intersect_moller(r, tri.v0, tri.v1, tri.v2, r.tmax, &t, &u, &v)))
            h = Hit{t, u, v, tri.prim};
        hits[i] = to_caller(r, h);
    }
}

namespace scalar {

namespace {

// The scalar reference of one ray vs one Tri8, closest hit: lanes in order,
// tmax shrinking to best.t. The SIMD kernels reproduce this exactly.
template <TriangleTest kTest>
bool tri8_closest(const PreparedRay& r, const Tri8& b, Hit& best) {
    bool changed = false;
    for (int i = 0; i < 8; ++i) {
        float t, u, v;
        if (intersect_triangle<kTest>(r, b.v0(i), b.v1(i), b.v2(i), best.t, &t, &u, &v) && closer(t, b.prim[i], best)) {
            best = Hit{t, u, v, b.prim[i]};
            changed = true;
        }
    }
    return changed;
}

template <TriangleTest kTest>
bool tri8_any(const PreparedRay& r, const Tri8& b, float tmax, Hit& hit) {
    for (int i = 0; i < 8; ++i) {
        float t, u, v;
        if (intersect_triangle<kTest>(r, b.v0(i), b.v1(i), b.v2(i), tmax, &t, &u, &v)) {
            hit = Hit{t, u, v, b.prim[i]};
            return true;
        }
    }
    return false;
}

template <TriangleTest kTest>
void closest(std::span<const Ray> rays, std::span<const Tri8> blocks, Hit* hits) {
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const PreparedRay r = prepare(rays[i]);
        Hit best;
        if (r.valid) {
            best.t = r.tmax;
            for (const Tri8& b : blocks) tri8_closest<kTest>(r, b, best);
            if (!best.hit()) best = Hit{};
        }
        hits[i] = to_caller(r, best);
    }
}

template <TriangleTest kTest>
void any(std::span<const Ray> rays, std::span<const Tri8> blocks, std::uint8_t* occluded, Hit* first_hits) {
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const PreparedRay r = prepare(rays[i]);
        Hit h;
        bool found = false;
        if (r.valid)
            for (const Tri8& b : blocks)
                if ((found = tri8_any<kTest>(r, b, r.tmax, h))) break;
        occluded[i] = found ? 1 : 0;
        if (first_hits) first_hits[i] = found ? to_caller(r, h) : Hit{};
    }
}

}  // namespace

Isa Kernels::compiled_isa() { return Isa::scalar; }

void Kernels::prepare_rays(std::span<const Ray> rays, const Aabb* bounds, PreparedRay* out, std::uint8_t* ok) {
    detail::note_isa_used(Isa::scalar);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        out[i] = prepare(rays[i]);
        float entry;
        ok[i] = bounds && out[i].valid && intersect_box(out[i], *bounds, out[i].tmax, &entry) ? 1 : 0;
    }
}

void Kernels::intersect_box8(std::span<const Ray> rays, const Box8& boxes, std::uint8_t* masks, float* entries) {
    detail::note_isa_used(Isa::scalar);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const PreparedRay r = prepare(rays[i]);
        std::uint32_t m = 0;
        for (int j = 0; j < 8; ++j) {
            float e = std::numeric_limits<float>::infinity();
            if (r.valid && intersect_box(r, boxes.get(j), r.tmax, &e)) m |= 1u << j;
            entries[8 * i + j] = r.valid ? to_caller_t(r, e) : e;
        }
        masks[i] = static_cast<std::uint8_t>(m);
    }
}

void Kernels::intersect_box8_groups(std::span<const Ray> rays, std::span<const Box8> supers,
                                    std::span<const Box8> groups, std::uint8_t* masks, float* entries) {
    detail::note_isa_used(Isa::scalar);
    const std::size_t ng = groups.size();
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const PreparedRay r = prepare(rays[i]);
        // A group is tested when there are no supers or the ray hits its super lane.
        auto tested = [&](std::size_t g) {
            if (supers.empty()) return true;
            float e = 0.0f;
            return r.valid && intersect_box(r, supers[g / 8].get(int(g % 8)), r.tmax, &e);
        };
        for (std::size_t g = 0; g < ng; ++g) {
            std::uint32_t m = 0;
            float* e8 = entries + 8 * (ng * i + g);
            const bool test = tested(g);
            for (int j = 0; j < 8; ++j) {
                float e = std::numeric_limits<float>::infinity();
                if (test && r.valid && intersect_box(r, groups[g].get(j), r.tmax, &e)) m |= 1u << j;
                e8[j] = test && r.valid ? to_caller_t(r, e) : std::numeric_limits<float>::infinity();
            }
            masks[ng * i + g] = static_cast<std::uint8_t>(m);
        }
    }
}

namespace {
// The reference box test (box.h) on each lane.
struct ScalarTreeTest {
    const Box8* nodes;
    const PreparedRay* ray(const PreparedRay& r) const { return &r; }
    std::uint32_t mask(const PreparedRay* r, std::uint32_t n, float* e) const {
        std::uint32_t m = 0;
        for (int j = 0; j < 8; ++j)
            if (intersect_box(*r, nodes[n].get(j), r->tmax, &e[j])) m |= 1u << j;
        return m;
    }
};
}  // namespace

detail::TreeWalk Kernels::collect_box8_tree(std::span<const Ray> rays, std::span<const std::uint8_t> live,
                                            std::span<const Box8> nodes, std::span<const std::uint32_t> children,
                                            std::size_t leaf_lanes, std::uint32_t* stack,
                                            std::pair<float, std::uint32_t>* out, std::size_t used, std::size_t cap,
                                            std::uint32_t* first) {
    detail::note_isa_used(Isa::scalar);
    return kernels::detail::walk_box_tree(rays, live, !nodes.empty(), children, leaf_lanes, stack, out, used, cap,
                                          first, ScalarTreeTest{nodes.data()});
}

detail::TreeWalk Kernels::collect_boxes(std::span<const Ray> rays, std::span<const std::uint8_t> live,
                                        std::span<const Box8> groups, std::size_t count,
                                        std::pair<float, std::uint32_t>* out, std::size_t used, std::size_t cap,
                                        std::uint32_t* first) {
    detail::note_isa_used(Isa::scalar);
    std::size_t i = 0;
    for (; i < rays.size(); ++i) {
        if (cap - used < count) break;
        first[i] = std::uint32_t(used);
        if (!live.empty() && live[i] == 0) continue;
        const PreparedRay r = prepare(rays[i]);
        if (!r.valid) continue;
        for (std::size_t b = 0; b < count; ++b) {
            float e;
            if (intersect_box(r, groups[b / 8].get(int(b % 8)), r.tmax, &e))
                out[used++] = {to_caller_t(r, e), std::uint32_t(b)};
        }
    }
    return {i, used};
}

std::uint64_t Kernels::count_box8_hits(std::span<const Ray> rays, std::span<const Box8> blocks) {
    detail::note_isa_used(Isa::scalar);
    std::uint64_t n = 0;
    for (const Ray& ray : rays) {
        const PreparedRay r = prepare(ray);
        if (!r.valid) continue;
        for (const Box8& b : blocks)
            for (int j = 0; j < 8; ++j) {
                float e;
                n += intersect_box(r, b.get(j), r.tmax, &e) ? 1 : 0;
            }
    }
    return n;
}

void Kernels::intersect_tri8(std::span<const Ray> rays, std::span<const Tri8> blocks, TriangleTest test, Hit* hits) {
    detail::note_isa_used(Isa::scalar);
    if (test == TriangleTest::watertight) closest<TriangleTest::watertight>(rays, blocks, hits);
    else closest<TriangleTest::moller>(rays, blocks, hits);
}

void Kernels::occluded_tri8(std::span<const Ray> rays, std::span<const Tri8> blocks, TriangleTest test,
                            std::uint8_t* occluded, Hit* first_hits) {
    detail::note_isa_used(Isa::scalar);
    if (test == TriangleTest::watertight) any<TriangleTest::watertight>(rays, blocks, occluded, first_hits);
    else any<TriangleTest::moller>(rays, blocks, occluded, first_hits);
}

}  // namespace scalar
}  // namespace simdbvh::kernels
