// Scene traversal: planes first (they clamp the ray), then the top level. A
// single ray walks the top-level BVH2 by the binary loop
// (bvh2/internal/simdbvh/bvh2/internal/traverse_binary-inl.h) with the slack box test and the instance
// leaf below, which maps the world ray into each visited instance and runs
// that geometry's bottom level; batches collect candidates from the 8-wide top
// level and trace them in rounds (below).
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

#include "simdbvh/kernels/batch.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/platform/parallel.h"
#include "scene_trace-inl.h"
#include "simdbvh/platform/internal/scratch_pool.h"
#include "simdbvh/bvh2/internal/traverse_binary-inl.h"

namespace simdbvh {

namespace {

using scene::detail::SlackBox2Test;

// A bottom level's traversals (the per-ISA wide ones: meshes, sphere sets,
// box sets, closest or any), for object-space rays: Hits in the rays' own parameter.
template <class Query, int N>
struct Bottom {
    scene::detail::WideFn<N> wide;
    scene::detail::ShapeFn<N, Sphere> spheres;
    scene::detail::ShapeFn<N, Aabb> boxes;
    static Bottom of(Isa isa) {
        constexpr bool kAny = Query::kAnyHit;
        return {scene::detail::wide_fn<N, kAny>(isa), scene::detail::shape_fn<N, Sphere, kAny>(isa),
                scene::detail::shape_fn<N, Aabb, kAny>(isa)};
    }
    void trace(const BottomLevel<N>& b, std::span<const Ray> obj, std::span<Hit> got) const {
        if (const BvhN<N>* bvh = std::get_if<BvhN<N>>(&b.tree)) {
            wide(*bvh, obj, got, TraceOptions{});
            return;
        }
        const ShapeTree<N>& t = std::get<ShapeTree<N>>(b.tree);
        if (!b.spheres.empty()) spheres(t, b.spheres.data(), b.bounds, obj, got);
        else boxes(t, b.boxes.data(), b.bounds, obj, got);
    }
    Hit trace(const BottomLevel<N>& b, const Ray& obj) const {
        Hit h;
        trace(b, std::span<const Ray>(&obj, 1), std::span<Hit>(&h, 1));
        return h;
    }
};

// Leaf intersector of the top level: the leaf's instances (top_instance). The scene hit is kept here in the caller's parameter;
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
        if (hit.hit()) obj.tmax = scene::detail::tmax_keeping_ties(hit.t);
        const Hit h = bottom.trace(scene->bottoms()[rec.geometry], obj);
        if (!h.hit() || !closer(h.t, inst, h.prim, hit)) return false;
        hit = SceneHit{h.t, h.u, h.v, h.prim, rec.geometry, inst};
        const float keep = scene::detail::tmax_keeping_ties(h.t);  // the culling distance, ties kept
        best.t = r.t_exp == 0 ? keep : std::ldexp(keep, -r.t_exp);
        best.prim = 0;
        return true;
    }
    void closest(const PreparedRay& r, std::uint32_t first, std::uint32_t count, Hit& best, TraceStats*) const {
        for (std::uint32_t k = 0; k < count; ++k) visit(r, scene->top_instance(first, k), best);
    }
    bool any(const PreparedRay& r, std::uint32_t first, std::uint32_t count, Hit& best, TraceStats*) const {
        for (std::uint32_t k = 0; k < count; ++k)
            if (visit(r, scene->top_instance(first, k), best)) return true;
        return false;
    }
};

template <class Query, int N>
SceneHit trace(const SceneBvhN<N>& s, const Ray& ray, Isa isa) {
    const PreparedRay pr = prepare(ray);
    if (!pr.valid) return {};
    const std::uint32_t ni = std::uint32_t(s.instances().size());
    InstanceLeaf<Query, N> leaf{&s, nullptr, Bottom<Query, N>::of(isa),
                                scene::detail::trace_planes<Query::kAnyHit>(s.planes(), pr, ni)};
    if (leaf.hit.hit() && Query::kAnyHit) return leaf.hit;
    if (s.top().nodes.empty()) return leaf.hit;
    Ray w = ray;
    if (leaf.hit.hit())
        w.tmax = scene::detail::tmax_keeping_ties(
            leaf.hit.t);  // equal-t hits are still found (inclusive tests), lower ids win
    leaf.world = &w;
    const float o = std::max({std::fabs(ray.org.x), std::fabs(ray.org.y), std::fabs(ray.org.z)});
    const SlackBox2Test test{s.slack_scale() * (o + s.scene_magnitude())};
    bvh2::traverse_binary<SlackBox2Test, Query, false>(s.top().nodes, leaf, w, nullptr, test);
    return leaf.hit;
}

// Batches: a wavefront over rounds instead of one ray at a time, so each
// bottom-level mesh is traced by the batched wide traversal (its rays in
// flight interleaved) rather than one call per instance visit. Per chunk of
// rays: planes, then each ray's candidate instances with their box entry
// distances (top level, no culling), nearest first; round k gives every live
// ray its k-th candidate, grouped by geometry (instances of one geometry
// next to each other, each ray in its instance's object space; one
// bottom-level call per geometry and round), with tmax = the ray's closest
// hit so far, skipping candidates whose entry is beyond that hit (the same
// cull_bound culling as the loop). Every candidate that can hold the closest
// hit is tested with a tmax at least its t (tests are inclusive) and merged by
// closer(), so the hits are those of trace() and of the brute force.
// The candidates: the chunk's live rays walk the wide top level (TopWide)
// in one batched kernel call (kernels::collect_box8_tree), which reports each
// ray's leaves with their entry distances; a leaf's instances share its entry.
// (With few leaves, kernels::collect_boxes tests the rays against the grown
// leaf boxes directly, with the same leaves and entries; TopWide in scene.h.)
// The leaf boxes are grown by the largest slack of the chunk's live rays, and
// each inner lane's box is the union of the lanes below it, so a ray reaches
// exactly the leaves whose grown boxes it enters: a superset of what the
// per-ray walk with its own slack gives (a larger box, the same conservative
// slab test; a box inside one the test misses is missed too). Extra
// candidates only add exact bottom-level tests whose hits are real, and hits
// are merged by closer(), so the results are trace()'s and the brute force's
// bit for bit. Against the earlier forms, one scalar BVH2 walk per ray (above
// 128 instances) and every instance box tested per ray in SIMD groups under
// union boxes (up to 128), callgrind over the batch trace (262,144 rays,
// closest + any, AVX2, BVH8): instances-1000 incoherent 3,263M -> 1,254M
// instructions and primary 1,946M -> 813M (walk -> this); instances-100
// 711M -> 654M and 553M -> 489M, room 572M -> 568M and 340M -> 319M (groups ->
// this); the same hits.
// A chunk's working arrays, kept from chunk to chunk and from call to call
// (every use below sizes and fills what it reads): about 130 bytes per ray of
// the largest chunk traced (4 MiB at 32,768 rays) plus 8 per candidate. Made
// afresh per chunk, their megabytes (1 MiB of object rays, 1 MiB of clamped
// world rays, 0.5 MiB of hits, ...) came from mmap whenever glibc's dynamic
// mmap threshold had not risen past them, which depends on the process's
// earlier allocations: page faults and zeroing on every chunk. In `simdbvh
// bench --scene room` (AMD Zen 4, one thread, 262,144 rays) that made ours
// 7.9 Mrays/s on primary closest hits where the Google Benchmark of the same
// scene and rays gave 10.8, and 11.0 with the threshold fixed at 32 MiB
// (GLIBC_TUNABLES=glibc.malloc.mmap_threshold).
struct ChunkScratch {
    std::vector<Ray> clamped, obj;
    std::vector<Hit> got;
    std::vector<std::pair<float, std::uint32_t>> cand, leaves;  // (entry, instance), (entry, BVH2 leaf)
    std::vector<std::uint32_t> first, at, leaf_ids, active, count, ids;
    std::vector<std::uint8_t> done, live;
    std::vector<int> plane;
    std::vector<float> plane_t;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs, sorted;  // (instance, ray)
    std::vector<Aabb> boxes, unions;
    std::vector<Box8> nodes;
};

template <int N>
void collect_tree(const SceneBvhN<N>& s, std::span<const Ray> world, const std::vector<std::uint8_t>& live, float slack,
                  Isa isa, ChunkScratch& x) {
    const std::size_t n = world.size();
    const TopWide& w = s.top_wide();
    const Bvh2Topology& top = s.top();
    const SlackBox2Test grow{slack};
    std::vector<std::pair<float, std::uint32_t>>& leaves = x.leaves;  // (entry, top-level BVH2 leaf)
    std::vector<std::uint32_t>& at = x.at;
    std::vector<std::pair<float, std::uint32_t>>& cand = x.cand;
    std::vector<std::uint32_t>& first = x.first;
    leaves.clear();
    at.assign(n + 1, 0);
    // With up to kCollectBoxesMax leaves, the rays against the grown leaf
    // boxes (kernels::collect_boxes: above 16 boxes each ray against the
    // unions of 8 leaf boxes, then the 8 boxes of each union it hits; up to
    // 16, 8 rays per vector against each box): the leaves a ray reaches
    // in the wide tree are exactly those whose grown boxes it hits (below),
    // with the same entries. When collect_boxes tested 8 rays per vector
    // against every box (ns per ray, tree walk -> boxes, 2026-11-28, commit
    // 348b986), it won on incoherent rays (instances-100 67 -> 53) and lost on
    // a camera's, which the walk culls well (instances-100 31 -> 44), so
    // coherent chunks took it only up to 32 leaves; under unions (commit
    // 21301c7) it wins on both (instances-48 and -100 primary rays +4-9% over
    // the walk, Mrays/s: docs/performance_log.md#scenes, "Rounds by geometry
    // and the top level under unions", commit ca13fea).
    std::vector<std::uint32_t>& leaf_ids = x.leaf_ids;
    leaf_ids.clear();
    for (const std::uint32_t c : w.children)
        if (c != kernels::kBoxTreeEmpty && (c & kernels::kBoxTreeLeaf) != 0)
            leaf_ids.push_back(c & ~kernels::kBoxTreeLeaf);
    if (leaf_ids.size() <= kernels::kCollectBoxesMax) {
        std::vector<Aabb>& boxes = x.boxes;
        boxes.resize(leaf_ids.size());
        for (std::size_t k = 0; k < leaf_ids.size(); ++k) boxes[k] = grow.grow(top.nodes[leaf_ids[k]].box);
        kernels::collect_boxes(world, live, boxes, leaves, at, isa);
        for (auto& [entry, leaf] : leaves) leaf = leaf_ids[leaf];
    } else {
        // Bottom up (children come after their parents): a leaf lane's box is
        // its BVH2 leaf's, grown; an inner lane's the union of its node's lanes.
        const std::size_t nw = w.children.size() / 8;
        std::vector<Box8>& nodes = x.nodes;
        std::vector<Aabb>& unions = x.unions;
        nodes.resize(nw);
        unions.assign(nw, Aabb{});
        for (std::size_t m = nw; m-- > 0;) {
            nodes[m].clear();
            for (int j = 0; j < 8; ++j) {
                const std::uint32_t c = w.children[8 * m + std::size_t(j)];
                if (c == kernels::kBoxTreeEmpty) continue;
                const bool leaf = (c & kernels::kBoxTreeLeaf) != 0;
                const Aabb b = leaf ? grow.grow(top.nodes[c & ~kernels::kBoxTreeLeaf].box) : unions[c];
                nodes[m].set(j, b);
                unions[m].grow(b);
            }
        }
        kernels::collect_box8_tree(world, live, nodes, w.children, leaves, at, isa);
    }
    for (std::size_t i = 0; i < n; ++i) {
        first[i] = std::uint32_t(cand.size());
        for (std::uint32_t k = at[i]; k < at[i + 1]; ++k) {
            const auto [entry, leaf] = leaves[k];
            const Node2& nd = top.nodes[leaf];
            for (std::uint32_t k = 0; k < nd.count; ++k) cand.push_back({entry, s.top_instance(nd.first, k)});
        }
        std::sort(cand.begin() + first[i], cand.end());
    }
}

// One instance (a sphere set, a single mesh, any one-object scene): the live
// rays go to the bottom level as one batch, without candidates or rounds. The
// rounds would give each live ray this one candidate, at entry -inf (never
// culled), and the bottom level tests its own bounds first (RayFeed in
// bvh8/internal/simdbvh/bvh8/internal/traverse-inl.h), so a top-level box test would only repeat that
// work; the merge is the rounds' own (closer() against a plane's hit).
template <class Query, int N>
void trace_one_instance(const SceneBvhN<N>& s, std::span<const Ray> world, const std::vector<std::uint8_t>& live,
                        std::span<SceneHit> hits, const Bottom<Query, N>& bottom, ChunkScratch& x) {
    const InstanceRecord& rec = s.instances()[0];
    std::vector<std::uint32_t>& ids = x.ids;
    std::vector<Ray>& obj = x.obj;
    ids.clear();
    obj.clear();
    for (std::size_t i = 0; i < world.size(); ++i) {
        if (!live[i]) continue;
        ids.push_back(std::uint32_t(i));
        obj.push_back(object_ray(rec.inv, world[i]));
        if (hits[i].hit()) obj.back().tmax = scene::detail::tmax_keeping_ties(hits[i].t);
    }
    std::vector<Hit>& got = x.got;
    got.resize(obj.size());
    bottom.trace(s.bottoms()[rec.geometry], obj, got);
    for (std::size_t j = 0; j < ids.size(); ++j) {
        const Hit& h = got[j];
        SceneHit& hit = hits[ids[j]];
        if (h.hit() && closer(h.t, 0, h.prim, hit)) hit = SceneHit{h.t, h.u, h.v, h.prim, rec.geometry, 0};
    }
}

// Instances ranked by geometry, then id: a round's pairs sorted by rank put
// every instance of a geometry next to each other, so the round traces each
// bottom level in one call. Empty when the instances' geometries are already
// in order (the rank is the id: instances-N, a single geometry).
std::vector<std::uint32_t> geometry_rank(const std::vector<InstanceRecord>& recs) {
    bool in_order = true;
    for (std::size_t i = 1; i < recs.size(); ++i) in_order &= recs[i - 1].geometry <= recs[i].geometry;
    if (in_order) return {};
    std::vector<std::uint32_t> order(recs.size());
    for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return recs[a].geometry < recs[b].geometry; });
    std::vector<std::uint32_t> rank(recs.size());
    for (std::uint32_t k = 0; k < order.size(); ++k) rank[order[k]] = k;
    return rank;
}

// Sorts a round's (instance, ray) pairs, made in ray order, by the
// instance's rank (geometry_rank; empty: the instance): a stable counting
// sort when the instances are few against the pairs, else std::sort by (rank,
// ray), the same order.
inline void group_by_instance(std::vector<std::pair<std::uint32_t, std::uint32_t>>& pairs, std::uint32_t ni,
                              std::span<const std::uint32_t> rank, std::vector<std::uint32_t>& count,
                              std::vector<std::pair<std::uint32_t, std::uint32_t>>& sorted) {
    const auto key = [&](std::uint32_t inst) { return rank.empty() ? inst : rank[inst]; };
    if (std::size_t(ni) > 4 * pairs.size()) {
        std::sort(pairs.begin(), pairs.end(), [&](const auto& a, const auto& b) {
            return std::pair(key(a.first), a.second) < std::pair(key(b.first), b.second);
        });
        return;
    }
    count.assign(std::size_t(ni) + 1, 0);
    for (const auto& p : pairs) ++count[key(p.first) + 1];
    for (std::uint32_t i = 0; i < ni; ++i) count[i + 1] += count[i];
    sorted.resize(pairs.size());
    for (const auto& p : pairs) sorted[count[key(p.first)]++] = p;
    pairs.swap(sorted);
}

template <class Query, int N>
void trace_chunk(const SceneBvhN<N>& s, std::span<const Ray> rays, std::span<SceneHit> hits,
                 const Bottom<Query, N>& bottom, std::span<const std::uint32_t> rank, Isa isa, ChunkScratch& x) {
    constexpr bool kAny = Query::kAnyHit;
    const std::size_t n = rays.size();
    const std::uint32_t ni = std::uint32_t(s.instances().size());
    // The world rays: the caller's, or for closest hits with planes a copy
    // whose tmax the planes' hits clamp (an any-hit ray that hits a plane is
    // done, so its tmax is never read: no copy, 10% of the room's primary
    // any-hit rays in perf). Without planes a ray needs no prepare here (the
    // validity test is prepare's own; the kernels prepare what they trace).
    const bool planes = !s.planes().empty();
    const bool clamp = planes && !kAny;
    std::vector<Ray>& clamped = x.clamped;
    if (clamp) clamped.assign(rays.begin(), rays.end());
    const std::span<const Ray> world = clamp ? std::span<const Ray>(clamped) : rays;
    std::vector<std::pair<float, std::uint32_t>>& cand = x.cand;  // (entry, instance)
    std::vector<std::uint32_t>& first = x.first;
    std::vector<std::uint8_t>& done = x.done;
    std::vector<std::uint8_t>& live = x.live;
    cand.clear();
    first.assign(n + 1, 0);
    done.assign(n, 0);
    live.assign(n, 0);
    // The planes of every ray first, four rays per vector (nearest_planes:
    // trace_planes' nearest_plane per ray, the same bits).
    std::vector<int>& plane = x.plane;
    std::vector<float>& plane_t = x.plane_t;
    if (planes) {
        plane.resize(n);
        plane_t.resize(n);
        nearest_planes(rays, s.planes(), kAny, plane, plane_t, isa);
    }
    float max_slack = 0.0f;
    std::size_t nlive = 0;
    for (std::size_t i = 0; i < n; ++i) {
        // A ray with a plane hit is valid (nearest_planes hits only valid
        // rays): the validity test is for the others.
        if (planes && plane[i] >= 0) {
            const std::uint32_t k = std::uint32_t(plane[i]);
            hits[i] = SceneHit{plane_t[i], 0.0f, 0.0f, k, kNoGeometry, ni + k};
            if (kAny) {
                done[i] = 1;
                continue;
            }
            clamped[i].tmax = scene::detail::tmax_keeping_ties(hits[i].t);
        } else {
            hits[i] = SceneHit{};
            if (!valid_ray(rays[i])) {
                done[i] = 1;
                continue;
            }
        }
        if (s.top().nodes.empty()) continue;
        const float o = std::max({std::fabs(rays[i].org.x), std::fabs(rays[i].org.y), std::fabs(rays[i].org.z)});
        const SlackBox2Test test{s.slack_scale() * (o + s.scene_magnitude())};
        live[i] = 1;
        ++nlive;
        max_slack = std::max(max_slack, test.slack);
    }
    if (nlive == 0) return;  // every ray done by the planes (any hit), invalid, or an empty top level
    if (ni == 1) {
        trace_one_instance(s, world, live, hits, bottom, x);
        return;
    }
    collect_tree(s, world, live, max_slack, isa, x);
    first[n] = std::uint32_t(cand.size());
    std::vector<std::pair<std::uint32_t, std::uint32_t>>& pairs = x.pairs;  // (instance, ray)
    std::vector<std::pair<std::uint32_t, std::uint32_t>>& sorted = x.sorted;
    std::vector<std::uint32_t>& count = x.count;
    std::vector<Ray>& obj = x.obj;
    std::vector<Hit>& got = x.got;
    // The rays with candidates left, in ray order: each round walks these
    // instead of the whole chunk, and drops the rays it finishes.
    std::vector<std::uint32_t>& active = x.active;
    active.clear();
    for (std::size_t i = 0; i < n; ++i)
        if (!done[i] && first[i] < first[i + 1]) active.push_back(std::uint32_t(i));
    for (std::uint32_t k = 0;; ++k) {
        pairs.clear();
        std::size_t kept = 0;
        for (const std::uint32_t i : active) {
            if (done[i] || first[i] + k >= first[i + 1]) continue;
            const auto [entry, inst] = cand[first[i] + k];
            if (hits[i].hit() && entry > cull_bound(hits[i].t)) {
                done[i] = 1;  // sorted: every later candidate is farther
                continue;
            }
            pairs.push_back({inst, i});
            active[kept++] = i;
        }
        active.resize(kept);
        if (pairs.empty()) break;
        group_by_instance(pairs, ni, rank, count, sorted);
        const std::vector<InstanceRecord>& recs = s.instances();
        for (std::size_t b = 0; b < pairs.size();) {
            const std::uint32_t geom = recs[pairs[b].first].geometry;
            std::size_t e = b;
            while (e < pairs.size() && recs[pairs[e].first].geometry == geom) ++e;
            const BottomLevel<N>& bl = s.bottoms()[geom];
            obj.resize(e - b);
            got.resize(e - b);
            for (std::size_t j = b; j < e; ++j) {
                const std::uint32_t i = pairs[j].second;
                Ray& r = obj[j - b];
                r = object_ray(recs[pairs[j].first].inv, world[i]);
                if (hits[i].hit()) r.tmax = scene::detail::tmax_keeping_ties(hits[i].t);
            }
            bottom.trace(bl, obj, got);
            for (std::size_t j = b; j < e; ++j) {
                const std::uint32_t i = pairs[j].second, inst = pairs[j].first;
                const Hit& h = got[j - b];
                if (h.hit() && closer(h.t, inst, h.prim, hits[i])) {
                    hits[i] = SceneHit{h.t, h.u, h.v, h.prim, geom, inst};
                    if (kAny) done[i] = 1;
                }
            }
            b = e;
        }
    }
}

template <class Query, int N>
void trace_span(const SceneBvhN<N>& s, std::span<const Ray> rays, std::span<SceneHit> hits, Isa isa, int threads) {
    simdbvh::detail::check_size(hits.size(), rays.size(), "hits");
    const auto bottom = Bottom<Query, N>::of(isa);  // the one ISA switch per batch
    const std::vector<std::uint32_t> rank = geometry_rank(s.instances());
    // Chunks as large as the threads allow, up to kChunkMax rays (scene.h): a round
    // groups a chunk's rays by geometry, and a bottom level traces each group
    // as one batch, so larger chunks give larger groups (fewer calls, more
    // rays in flight per call). Grouped by instance (one call per instance
    // and round, as before commit f3ad2f6), rays per group (incoherent rays, 2048 ->
    // 32768 rays per chunk): instances-100 5.1 -> 48, instances-1000 1.6 ->
    // 8.3; by geometry, every ray of a round in one call (their instances'
    // object spaces side by side): Mrays/s (AMD Zen 4, one pinned thread,
    // 262,144 rays, simdbvh_bench_scene_desc, by instance -> by geometry,
    // two rounds alternating) instances-100 BVH8 AVX-512 interior closest
    // 5.25-5.38 -> 5.60-5.85, primary closest 9.33-9.71 -> 11.00-11.69;
    // instances-1000 (one round) 2.22 -> 2.63 and 4.37 -> 5.58; the room level. Best ours over Embree (AVX-512, AMD Zen 4, ABBA 2 rounds, 262,144
    // rays), 2048 -> 32768: instances-100 interior closest
    // 0.91-0.92 -> 1.06-1.08, interior any 0.81-0.83 -> 0.97-1.00;
    // instances-1000 interior closest 0.69-0.77 -> 0.91-0.93; the room level
    // or better. 65536 and 131072 gave no more (instances-1000).
    constexpr std::size_t kChunkMin = 2048, kChunkMax = kSceneChunkRays;
    const int nt = std::max(1, threads);
    const std::size_t chunk = std::clamp((rays.size() + std::size_t(nt) - 1) / std::size_t(nt), kChunkMin, kChunkMax);
    const std::size_t chunks = (rays.size() + chunk - 1) / chunk;
    // One item per chunk (grain 1): with parallel_for's default grain of
    // 2048 items, a batch of fewer than 2048 chunks (every batch below 67M
    // rays) ran on the calling thread alone, whatever `threads` said.
    auto& pool = detail::ScratchPool<ChunkScratch>::of_this_thread();
    ParallelOptions po;
    po.grain = 1;
    parallel_for(
        chunks, nt,
        [&](std::size_t cb, std::size_t ce) {
            std::unique_ptr<ChunkScratch> x = pool.take();
            for (std::size_t c = cb; c < ce; ++c) {
                const std::size_t b = c * chunk, e = std::min(rays.size(), b + chunk);
                trace_chunk<Query>(s, rays.subspan(b, e - b), hits.subspan(b, e - b), bottom, rank, isa, *x);
            }
            pool.give(std::move(x));
        },
        po);
}

}  // namespace

template <int N>
SceneHit intersect(const SceneBvhN<N>& s, const Ray& ray, const SceneTraceOptions& o) {
    return trace<query::ClosestHit>(s, ray, o.isa.value_or(active_isa()));
}
template <int N>
SceneHit occluded(const SceneBvhN<N>& s, const Ray& ray, const SceneTraceOptions& o) {
    return trace<query::AnyHit>(s, ray, o.isa.value_or(active_isa()));
}
template <int N>
void intersect(const SceneBvhN<N>& s, std::span<const Ray> rays, std::span<SceneHit> hits, const SceneTraceOptions& o) {
    trace_span<query::ClosestHit>(s, rays, hits, o.isa.value_or(active_isa()), o.threads);
}
template <int N>
void occluded(const SceneBvhN<N>& s, std::span<const Ray> rays, std::span<SceneHit> hits, const SceneTraceOptions& o) {
    trace_span<query::AnyHit>(s, rays, hits, o.isa.value_or(active_isa()), o.threads);
}

#define SIMDBVH_SCENE_WIDTH(N)                                                                 \
    template SceneHit intersect<N>(const SceneBvhN<N>&, const Ray&, const SceneTraceOptions&); \
    template SceneHit occluded<N>(const SceneBvhN<N>&, const Ray&, const SceneTraceOptions&);  \
    template void intersect<N>(const SceneBvhN<N>&, std::span<const Ray>, std::span<SceneHit>, \
                               const SceneTraceOptions&);                                      \
    template void occluded<N>(const SceneBvhN<N>&, std::span<const Ray>, std::span<SceneHit>, const SceneTraceOptions&);
SIMDBVH_SCENE_WIDTH(4)
SIMDBVH_SCENE_WIDTH(8)
SIMDBVH_SCENE_WIDTH(16)
#undef SIMDBVH_SCENE_WIDTH

}  // namespace simdbvh
