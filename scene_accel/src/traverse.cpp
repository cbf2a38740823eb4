// Scene traversal: planes first (they clamp the ray), then the top-level
// BVH2 by the binary loop (bvh2/src/traverse_binary-inl.h) with the slack box
// test and the instance leaf below, which maps the world ray into each visited
// instance and runs that geometry's bottom level.
#include <cmath>
#include <type_traits>

#include "simdbvh/kernels/error.h"
#include "simdbvh/kernels/parallel.h"
#include "scene_trace-inl.h"
#include "traverse_binary-inl.h"

namespace simdbvh {

namespace {

using scene_accel::ShapeLeaf;
using scene_accel::SlackBox2Test;

// A bottom level for an object-space ray: a Hit in the ray's own parameter.
template <class Query, int N>
struct Bottom {
    scene_accel::WideFn<N> wide;  // the per-ISA wide traversal (closest or any)
    Hit trace(const BottomLevel<N>& b, const Ray& obj) const {
        Hit h;
        if (const BvhN<N>* bvh = std::get_if<BvhN<N>>(&b.tree)) {
            wide(*bvh, std::span<const Ray>(&obj, 1), std::span<Hit>(&h, 1), TraceOptions{});
            return h;
        }
        const Bvh2Topology& t = std::get<Bvh2Topology>(b.tree);
        if (!b.spheres.empty())
            return bvh2::traverse_binary<SlackBox2Test, Query, false>(
                t.nodes, ShapeLeaf<Sphere>{b.spheres.data(), t.prim_ids.data()}, obj, nullptr);
        return bvh2::traverse_binary<SlackBox2Test, Query, false>(
            t.nodes, ShapeLeaf<Aabb>{b.boxes.data(), t.prim_ids.data()}, obj, nullptr);
    }
};

// Leaf intersector of the top level: the leaf's instances (ids = the top
// tree's prim_ids). The scene hit is kept here in the caller's parameter;
// the loop's `best` only carries the culling distance in its own.
template <class Query, int N>
struct InstanceLeaf {
    const SceneBvhN<N>* scene;
    const Ray* world;
    Bottom<Query, N> bottom;
    mutable SceneHit hit;

    bool visit(const PreparedRay& r, std::uint32_t inst, Hit& best) const {
        const InstanceRecord& rec = scene->instances()[inst];
        Ray obj = object_ray(rec.inv, *world);
        if (hit.hit()) obj.tmax = hit.t;
        const Hit h = bottom.trace(scene->bottoms()[rec.geometry], obj);
        if (!h.hit() || !closer(h.t, inst, h.prim, hit)) return false;
        hit = SceneHit{h.t, h.u, h.v, h.prim, rec.geometry, inst};
        best.t = r.t_exp == 0 ? h.t : std::ldexp(h.t, -r.t_exp);
        best.prim = 0;
        return true;
    }
    void closest(const PreparedRay& r, std::uint32_t first, std::uint32_t count, Hit& best, TraceStats*) const {
        const std::uint32_t* ids = scene->top().prim_ids.data();
        for (std::uint32_t i = first; i < first + count; ++i) visit(r, ids[i], best);
    }
    bool any(const PreparedRay& r, std::uint32_t first, std::uint32_t count, Hit& best, TraceStats*) const {
        const std::uint32_t* ids = scene->top().prim_ids.data();
        for (std::uint32_t i = first; i < first + count; ++i)
            if (visit(r, ids[i], best)) return true;
        return false;
    }
};

template <class Query, int N>
SceneHit trace(const SceneBvhN<N>& s, const Ray& ray, scene_accel::WideFn<N> wide) {
    const PreparedRay pr = prepare(ray);
    if (!pr.valid) return {};
    const std::uint32_t ni = std::uint32_t(s.instances().size());
    InstanceLeaf<Query, N> leaf{&s, nullptr, {wide}, scene_accel::trace_planes<Query::kAnyHit>(s.planes(), pr, ni)};
    if (leaf.hit.hit() && Query::kAnyHit) return leaf.hit;
    if (s.top().nodes.empty()) return leaf.hit;
    Ray w = ray;
    if (leaf.hit.hit()) w.tmax = leaf.hit.t;  // equal-t hits are still found (inclusive tests), lower ids win
    leaf.world = &w;
    const float o = std::max({std::fabs(ray.org.x), std::fabs(ray.org.y), std::fabs(ray.org.z)});
    const SlackBox2Test test{s.slack_scale() * (o + s.scene_magnitude())};
    bvh2::traverse_binary<SlackBox2Test, Query, false>(s.top().nodes, leaf, w, nullptr, test);
    return leaf.hit;
}

template <class Query, int N>
void trace_span(const SceneBvhN<N>& s, std::span<const Ray> rays, std::span<SceneHit> hits, Isa isa, int threads) {
    if (hits.size() < rays.size()) throw Error("hits span is smaller than rays span");
    const auto wide = scene_accel::wide_fn<N, Query::kAnyHit>(isa);  // the one ISA switch per batch
    parallel_for(rays.size(), std::max(1, threads), [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) hits[i] = trace<Query>(s, rays[i], wide);
    });
}

}  // namespace

template <int N>
SceneHit intersect(const SceneBvhN<N>& s, const Ray& ray, Isa isa) {
    return trace<query::ClosestHit>(s, ray, scene_accel::wide_fn<N, false>(isa));
}
template <int N>
SceneHit occluded(const SceneBvhN<N>& s, const Ray& ray, Isa isa) {
    return trace<query::AnyHit>(s, ray, scene_accel::wide_fn<N, true>(isa));
}
template <int N>
void intersect(const SceneBvhN<N>& s, std::span<const Ray> rays, std::span<SceneHit> hits, Isa isa, int threads) {
    trace_span<query::ClosestHit>(s, rays, hits, isa, threads);
}
template <int N>
void occluded(const SceneBvhN<N>& s, std::span<const Ray> rays, std::span<SceneHit> hits, Isa isa, int threads) {
    trace_span<query::AnyHit>(s, rays, hits, isa, threads);
}

#define SIMDBVH_SCENE_WIDTH(N)                                                                                    \
    template SceneHit intersect<N>(const SceneBvhN<N>&, const Ray&, Isa);                                         \
    template SceneHit occluded<N>(const SceneBvhN<N>&, const Ray&, Isa);                                          \
    template void intersect<N>(const SceneBvhN<N>&, std::span<const Ray>, std::span<SceneHit>, Isa, int);         \
    template void occluded<N>(const SceneBvhN<N>&, std::span<const Ray>, std::span<SceneHit>, Isa, int);
SIMDBVH_SCENE_WIDTH(4)
SIMDBVH_SCENE_WIDTH(8)
SIMDBVH_SCENE_WIDTH(16)
#undef SIMDBVH_SCENE_WIDTH

}  // namespace simdbvh
