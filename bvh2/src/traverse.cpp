// BVH2 traversal: the binary loop (traverse_binary-inl.h) with the box node
// test; reciprocal direction once per ray (prepare), near child first, the
// closest hit so far culls boxes and stack entries.
#include <cmath>
#include <type_traits>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/kernels/box.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/platform/parallel.h"
#include "simdbvh/bvh2/internal/traverse_binary-inl.h"

namespace simdbvh {

namespace {

// The width-2 node test of the BVH2: the two adjacent child boxes.
// BoxTest::plain: no Ize widening and no cull_bound margin, a comparison variant only
// (it may reject a box whose triangle the ray hits).
template <BoxTest kBox>
struct Box2Test {
    static constexpr float kWiden = kBox == BoxTest::conservative ? kFarWiden : 1.0f;
    static bool root(const PreparedRay& r, const Node2& n, float tmax, float* entry) {
        return intersect_box(r, n.box, tmax, entry, kWiden);
    }
    static std::uint32_t children(const PreparedRay& r, const Node2* nodes, const Node2& n, float tmax, float* e) {
        const bool ha = intersect_box(r, nodes[n.first].box, tmax, &e[0], kWiden);
        const bool hb = intersect_box(r, nodes[n.first + 1].box, tmax, &e[1], kWiden);
        return std::uint32_t(ha) | (std::uint32_t(hb) << 1);
    }
    static float cull(float t) { return kBox == BoxTest::conservative ? cull_bound(t) : t; }
};

template <TriangleTest kTest, BoxTest kBox, bool kAnyHit, bool kStats>
Hit traverse(const Bvh2& bvh, const Ray& ray, TraceStats* stats) {
    using Query = std::conditional_t<kAnyHit, query::AnyHit, query::ClosestHit>;
    const bvh2::TriangleLeaf<kTest, kStats> leaf{bvh.triangles().data(), bvh.prim_ids().data()};
    return bvh2::traverse_binary<Box2Test<kBox>, Query, kStats>(bvh.nodes(), leaf, ray, stats);
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
        return with_variant<true>(
            o, [&](auto v) { return traverse<decltype(v)::test, decltype(v)::box, kAnyHit, true>(bvh, ray, o.stats); });
    return with_variant<false>(
        o, [&](auto v) { return traverse<decltype(v)::test, decltype(v)::box, kAnyHit, false>(bvh, ray, nullptr); });
}

template <TriangleTest kTest, BoxTest kBox, bool kAnyHit, bool kStats>
void traverse_span(const Bvh2& bvh, std::span<const Ray> rays, std::span<Hit> hits, TraceStats* stats) {
    for (std::size_t i = 0; i < rays.size(); ++i) hits[i] = traverse<kTest, kBox, kAnyHit, kStats>(bvh, rays[i], stats);
}

template <bool kAnyHit>
void dispatch_span(const Bvh2& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& o) {
    simdbvh::detail::check_size(hits.size(), rays.size(), "hits");
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
