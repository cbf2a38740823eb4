// BVH2 stack traversal: reciprocal direction once per ray (prepare), near
// child first, the closest hit so far culls boxes and stack entries.
#include <cmath>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/kernels/box.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/kernels/parallel.h"

namespace simdbvh {

namespace {

struct StackEntry {
    std::uint32_t node;
    float entry;
};
// Children are pushed one at a time, so the stack never holds more entries
// than the tree is deep.
constexpr int kStackSize = kMaxDepth + 1;

template <BoxTest kBox>
inline bool box_test(const PreparedRay& r, const Aabb& b, float tmax, float* entry) {
    // BoxTest::plain: no Ize widening (and no kCullWiden below). A comparison
    // variant only: it may reject a box whose triangle the ray hits.
    return intersect_box(r, b, tmax, entry, kBox == BoxTest::conservative ? kFarWiden : 1.0f);
}
template <BoxTest kBox>
constexpr float kCull = kBox == BoxTest::conservative ? kCullWiden : 1.0f;

template <TriangleTest kTest, BoxTest kBox, bool kAnyHit, bool kStats>
Hit traverse(const Bvh2& bvh, const Ray& ray, TraceStats* stats) {
    Hit best;
    const PreparedRay r = prepare(ray);
    if (kStats) stats->rays++;
    const auto& nodes = bvh.nodes();
    if (!r.valid || nodes.empty()) return best;
    const TriangleVerts* tris = bvh.triangles().data();
    const std::uint32_t* ids = bvh.prim_ids().data();
    best.t = r.tmax;
    StackEntry stack[kStackSize];
    int sp = 0;
    float entry;
    if (kStats) stats->box_tests++;
    if (!box_test<kBox>(r, nodes[0].box, best.t, &entry)) return Hit{};
    std::uint32_t idx = 0;
    for (;;) {
        const Node2& n = nodes[idx];
        if (kStats) stats->nodes_visited++;
        if (!n.is_leaf()) {
            const Node2& a = nodes[n.first];
            const Node2& b = nodes[n.first + 1];
            float ea, eb;
            const float cull = best.t * kCull<kBox>;
            const bool ha = box_test<kBox>(r, a.box, cull, &ea);
            const bool hb = box_test<kBox>(r, b.box, cull, &eb);
            if (kStats) stats->box_tests += 2;
            if (ha && hb) {
                const bool a_first = ea <= eb;
                stack[sp++] = {a_first ? n.first + 1 : n.first, a_first ? eb : ea};
                idx = a_first ? n.first : n.first + 1;
                continue;
            }
            if (ha || hb) {
                idx = ha ? n.first : n.first + 1;
                continue;
            }
        } else {
            for (std::uint32_t i = n.first, e = n.first + n.count; i < e; ++i) {
                const TriangleVerts& tv = tris[i];
                float t, u, v;
                if (kStats) stats->triangle_tests++;
                if (intersect_triangle<kTest>(r, tv.v0, tv.v1, tv.v2, best.t, &t, &u, &v)) {
                    const std::uint32_t prim = ids[i];
                    if (kAnyHit) return to_caller(r, Hit{t, u, v, prim});
                    if (closer(t, prim, best)) best = {t, u, v, prim};
                }
            }
        }
        // Pop the nearest pending node still in front of the closest hit.
        for (;;) {
            if (sp == 0) return best.hit() ? to_caller(r, best) : Hit{};
            const StackEntry& s = stack[--sp];
            if (s.entry <= best.t * kCull<kBox>) {
                idx = s.node;
                break;
            }
        }
    }
}

// One switch over (triangle test, box test, stats) per call: calls
// f(tag<kTest, kBox, kStats>{}) with the options as template arguments.
template <TriangleTest kTest, BoxTest kBox, bool kStats>
struct Variant {
    static constexpr TriangleTest test = kTest;
    static constexpr BoxTest box = kBox;
    static constexpr bool stats = kStats;
};

template <bool kStats, typename F>
decltype(auto) with_variant(const TraceOptions& o, F&& f) {
    constexpr auto wt = TriangleTest::watertight, mt = TriangleTest::moller;
    constexpr auto cons = BoxTest::conservative, plain = BoxTest::plain;
    if (o.test == wt) return o.box == cons ? f(Variant<wt, cons, kStats>{}) : f(Variant<wt, plain, kStats>{});
    return o.box == cons ? f(Variant<mt, cons, kStats>{}) : f(Variant<mt, plain, kStats>{});
}

template <bool kAnyHit>
Hit dispatch(const Bvh2& bvh, const Ray& ray, const TraceOptions& o) {
    if (o.stats)
        return with_variant<true>(o, [&](auto v) {
            return traverse<decltype(v)::test, decltype(v)::box, kAnyHit, true>(bvh, ray, o.stats);
        });
    return with_variant<false>(o, [&](auto v) {
        return traverse<decltype(v)::test, decltype(v)::box, kAnyHit, false>(bvh, ray, nullptr);
    });
}

template <TriangleTest kTest, BoxTest kBox, bool kAnyHit, bool kStats>
void traverse_span(const Bvh2& bvh, std::span<const Ray> rays, std::span<Hit> hits, TraceStats* stats) {
    for (std::size_t i = 0; i < rays.size(); ++i)
        hits[i] = traverse<kTest, kBox, kAnyHit, kStats>(bvh, rays[i], stats);
}

template <bool kAnyHit>
void dispatch_span(const Bvh2& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& o) {
    if (hits.size() < rays.size()) throw Error("hits span is smaller than rays span");
    if (o.stats) {
        with_variant<true>(o, [&](auto v) {
            traverse_span<decltype(v)::test, decltype(v)::box, kAnyHit, true>(bvh, rays, hits, o.stats);
        });
    } else {
        parallel_for(rays.size(), o.threads, [&](std::size_t b, std::size_t e) {
            auto r = rays.subspan(b, e - b);
            auto h = hits.subspan(b, e - b);
            with_variant<false>(o, [&](auto v) {
                traverse_span<decltype(v)::test, decltype(v)::box, kAnyHit, false>(bvh, r, h, nullptr);
            });
        });
    }
}

}  // namespace

Hit intersect(const Bvh2& bvh, const Ray& ray, const TraceOptions& o) { return dispatch<false>(bvh, ray, o); }
Hit occluded(const Bvh2& bvh, const Ray& ray, const TraceOptions& o) { return dispatch<true>(bvh, ray, o); }
void intersect(const Bvh2& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& o) {
    dispatch_span<false>(bvh, rays, hits, o);
}
void occluded(const Bvh2& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& o) {
    dispatch_span<true>(bvh, rays, hits, o);
}

}  // namespace simdbvh
