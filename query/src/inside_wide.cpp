// Exact inside/outside over BvhN<N> (simdbvh/query/inside_wide.h): the BVH2's
// crossing count (query/internal/simdbvh/query/internal/crossing-inl.h) over wide nodes and Tri8 blocks.
// The column tests run 4 lanes at a time with SSE (the x86-64 baseline: no
// dispatch, no AVX); they are comparisons only, so they decide exactly what
// RayFrame::reaches() and column_misses() (on the mapped coordinates) decide
// in the BVH2's loop.
#include "simdbvh/query/inside_wide.h"
#include "simdbvh/kernels/error.h"

#include "simdbvh/kernels/internal/simd/sse2.h"

#include <cstddef>

#include "simdbvh/query/internal/crossing-inl.h"
#include "simdbvh/bvh8/internal/prefetch-inl.h"
#include "simdbvh/bvh8/internal/tri8_lanes-inl.h"
#include "simdbvh/query/internal/point_query-inl.h"
#include "simdbvh/platform/parallel.h"

namespace simdbvh {
namespace {

// The column of p's ray (a RayFrame): the boxes whose closed extent in u and
// v holds p and that reach p along w: hi_w >= p_w up, lo_w <= p_w down. Down
// is tested as -lo_w >= -p_w, the sign bits flipped by `flip` (exact, NaN
// stays NaN), so both directions run the same instructions; the planes are
// addressed by offset, so a column along any axis costs what +z did.
struct Column {
    __m128 pu, pv, pw, flip;  // pw and flip: p_w and the bound along w, sign-flipped down
    int u, v, w;
    bool up;
    Column() = default;
    Column(const detail::RayFrame& f, const Vec3& p) : u(f.u), v(f.v), w(f.w), up(f.up) {
        flip = f.up ? _mm_setzero_ps() : _mm_set1_ps(-0.0f);
        pu = _mm_set1_ps(p[u]);
        pv = _mm_set1_ps(p[v]);
        pw = _mm_xor_ps(_mm_set1_ps(p[w]), flip);
    }
    int reaches(__m128 lu, __m128 hu, __m128 lv, __m128 hv, __m128 bound_w) const {
        const __m128 in_u = _mm_and_ps(_mm_cmple_ps(lu, pu), _mm_cmple_ps(pu, hu));
        const __m128 in_v = _mm_and_ps(_mm_cmple_ps(lv, pv), _mm_cmple_ps(pv, hv));
        const __m128 in_w = _mm_cmple_ps(pw, _mm_xor_ps(bound_w, flip));
        return _mm_movemask_ps(_mm_and_ps(_mm_and_ps(in_u, in_v), in_w));
    }
};

// Child boxes the column reaches (empty slots: lo +inf, hi -inf, never). A
// BoxN's planes are lo_x, hi_x, lo_y, hi_y, lo_z, hi_z, N floats each.
template <int N>
std::uint32_t reached_children(const BoxN<N>& b, const Column& c) {
    static_assert(offsetof(BoxN<N>, hi_z) == 5 * N * sizeof(float));
    const float* plane = reinterpret_cast<const float*>(&b);
    const float *lu = plane + 2 * c.u * N, *lv = plane + 2 * c.v * N, *bw = plane + (2 * c.w + c.up) * N;
    std::uint32_t m = 0;
    for (int i = 0; i < N; i += 4)
        m |= std::uint32_t(c.reaches(_mm_load_ps(lu + i), _mm_load_ps(lu + N + i), _mm_load_ps(lv + i),
                                     _mm_load_ps(lv + N + i), _mm_load_ps(bw + i)))
             << i;
    return m;
}

// Triangles of a block whose column test passes (column_misses() false on the
// mapped coordinates; the vertices are finite, so min/max agree with
// fmin/fmax). A Tri8's planes are v0x, v0y, v0z, v1x, ..., 8 floats each.
std::uint32_t reached_triangles(const Tri8& t, const Column& c) {
    static_assert(offsetof(Tri8, v2z) == 8 * kBlockWidth * sizeof(float));
    const float* plane = reinterpret_cast<const float*>(&t);
    auto axis = [&](int k, int i, __m128& lo, __m128& hi) {
        const __m128 a = _mm_load_ps(plane + k * kBlockWidth + i), b = _mm_load_ps(plane + (3 + k) * kBlockWidth + i),
                     d = _mm_load_ps(plane + (6 + k) * kBlockWidth + i);
        lo = _mm_min_ps(_mm_min_ps(a, b), d);
        hi = _mm_max_ps(_mm_max_ps(a, b), d);
    };
    std::uint32_t m = 0;
    for (int i = 0; i < kBlockWidth; i += 4) {
        __m128 lu, hu, lv, hv, lw, hw;
        axis(c.u, i, lu, hu);
        axis(c.v, i, lv, hv);
        axis(c.w, i, lw, hw);
        m |= std::uint32_t(c.reaches(lu, hu, lv, hv, c.up ? hw : lw)) << i;
    }
    return m;
}

template <int N>
void count_leaf(detail::CrossingCounter& cnt, const Tri8* blocks, ChildN<N> leaf, const Column& col,
                const detail::RayFrame& f, const Vec3& p) {
    for (std::uint32_t b = 0; b < leaf.blocks(); ++b) {
        const Tri8& t = blocks[leaf.index + b];
        // A single-block leaf counts its own lanes only (its block may be shared).
        const std::uint32_t own = leaf.own_lanes() != 0 ? leaf.own_lanes() : detail::used_lanes(t);
        for (std::uint32_t m = reached_triangles(t, col) & own; m != 0; m &= m - 1) {
            const int k = __builtin_ctz(m);
            cnt.add(detail::crossing_exact(f, t.v0(k), t.v1(k), t.v2(k), p));
        }
    }
}

// Uninitialized stack entries (ChildN's member initializers would zero-fill
// several KiB per point: a fifth of the query's time in a profile).
struct Entry {
    std::uint32_t index, count;
};

// One point's walk: visits every node and leaf whose box the column of its
// ray reaches, in any order (a count does not depend on it).
template <int N>
struct Walk {
    detail::CrossingCounter cnt;
    detail::RayFrame frame;
    Column col;
    Vec3 p;
    ChildN<N> cur;
    std::uint32_t point;
    int sp;
    Entry stack[1 + (N - 1) * kMaxDepth];

    // False (and nothing to walk) when the column misses the tree.
    bool start(const BvhN<N>& bvh, const Vec3& q, std::uint32_t i, const InsideOptions& o) {
        cnt = {};
        p = q;
        point = i;
        frame = {};
        if (!detail::usable(q) || bvh.nodes().empty()) return false;
        frame = detail::ray_frame(o.ray, bvh.bounds(), q);
        if (!frame.reaches(bvh.bounds(), q)) return false;
        col = Column(frame, q);
        cur = ChildN<N>::inner(0);
        sp = 0;
        return true;
    }
    // Visits cur, then moves cur to the next node or leaf; true when done.
    bool step(const NodeN<N>* nodes, const Tri8* blocks) {
        if (cur.is_inner()) {
            const NodeN<N>& n = nodes[cur.index];
            std::uint32_t m = reached_children<N>(n.boxes, col);
            if (m != 0) {
                cur = n.children[__builtin_ctz(m)];
                for (m &= m - 1; m != 0; m &= m - 1) {
                    const ChildN<N>& c = n.children[__builtin_ctz(m)];
                    stack[sp++] = {c.index, c.count};
                }
                return false;
            }
        } else {
            count_leaf<N>(cnt, blocks, cur, col, frame, p);
        }
        if (sp == 0) return true;
        --sp;
        cur = ChildN<N>{stack[sp].index, stack[sp].count};
        return false;
    }
};

// Points walked in flight per loop: each step ends by prefetching the walk's
// next node or leaf, and the other walks' steps run while it arrives (uniform
// points visit about 3.5 BVH8 nodes each on the dragon, nearly every one a
// miss: without this the query waited on memory).
inline constexpr int kInFlight = 8;
inline constexpr std::size_t kPointAhead = 8;

// Classifies points[order[b..e)] into out.
template <int N>
void classify_span(const BvhN<N>& bvh, std::span<const Vec3> points, const std::uint32_t* order, std::size_t b,
                   std::size_t e, std::span<PointSide> out, const InsideOptions& o) {
    const NodeN<N>* nodes = bvh.nodes().data();
    const Tri8* blocks = bvh.blocks().data();
    Walk<N> walks[kInFlight];
    int live[kInFlight], nlive = 0;
    std::size_t next = b;
    auto refill = [&](int slot) {
        while (next < e) {
            // Morton order reads the points out of order: fetch one a few
            // walks ahead (this load was a third of the query's time).
            if (next + kPointAhead < e) {
                __builtin_prefetch(&points[order[next + kPointAhead]]);
                __builtin_prefetch(&out[order[next + kPointAhead]], 1);
            }
            const std::uint32_t i = order[next++];
            if (walks[slot].start(bvh, points[i], i, o)) return true;
            out[i] = walks[slot].cnt.result(o, walks[slot].frame.ray());
        }
        return false;
    };
    for (int w = 0; w < kInFlight; ++w)
        if (refill(w)) live[nlive++] = w;
    while (nlive > 0) {
        for (int k = 0; k < nlive;) {
            Walk<N>& w = walks[live[k]];
            if (!w.step(nodes, blocks)) {
                bvh8::detail::prefetch_child(nodes, blocks, w.cur);
            } else {
                out[w.point] = w.cnt.result(o, w.frame.ray());
                if (!refill(live[k])) {
                    live[k] = live[--nlive];
                    continue;
                }
            }
            ++k;
        }
    }
}

}  // namespace

template <int N>
PointSide classify_point(const BvhN<N>& bvh, const Vec3& p, const InsideOptions& opts) {
    PointSide r;
    const std::uint32_t zero = 0;
    classify_span(bvh, std::span<const Vec3>(&p, 1), &zero, 0, 1, std::span<PointSide>(&r, 1), opts);
    return r;
}

template <int N>
void classify_points(const BvhN<N>& bvh, std::span<const Vec3> points, std::span<PointSide> out,
                     const InsideOptions& opts) {
    simdbvh::detail::check_size(out.size(), points.size(), "out");
    // Morton order: neighbouring points walk the same nodes while they are in
    // cache. The order changes the speed only.
    const std::vector<std::uint32_t> order = detail::morton_order(points, opts.threads);
    parallel_for(
        points.size(), opts.threads,
        [&](std::size_t b, std::size_t e) { classify_span(bvh, points, order.data(), b, e, out, opts); },
        ParallelOptions{.grain = 1024});
}

#define SIMDBVH_INSTANTIATE(N)                                                               \
    template PointSide classify_point<N>(const BvhN<N>&, const Vec3&, const InsideOptions&); \
    template void classify_points<N>(const BvhN<N>&, std::span<const Vec3>, std::span<PointSide>, const InsideOptions&);
SIMDBVH_INSTANTIATE(4)
SIMDBVH_INSTANTIATE(8)
SIMDBVH_INSTANTIATE(16)
#undef SIMDBVH_INSTANTIATE

}  // namespace simdbvh
