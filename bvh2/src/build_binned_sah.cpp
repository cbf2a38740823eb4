// Binned SAH builder (Wald 2007, "On fast Construction of SAH-based Bounding
// Volume Hierarchies"), with SAH leaf-cost termination and a depth cap.
// Binning and partitioning stream over contiguous PrimRefs with SSE (the
// x86-64 baseline, no AVX); min/max operand order matches Aabb::grow exactly.
#include "simdbvh/kernels/internal/simd/sse2.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>
#include <type_traits>
#include <vector>

#include "build_common.h"
#include "simdbvh/platform/parallel.h"

namespace simdbvh::detail {

namespace {

constexpr int kMaxBins = 256;

struct Box4 {  // lo, hi as 4-lane vectors; lane 3 is ignored
    __m128 lo = _mm_set1_ps(std::numeric_limits<float>::infinity());
    __m128 hi = _mm_set1_ps(-std::numeric_limits<float>::infinity());
    void grow(__m128 l, __m128 h) {
        lo = _mm_min_ps(l, lo);  // == min_ps(l, lo): l < lo ? l : lo
        hi = _mm_max_ps(h, hi);
    }
    void grow(const Box4& b) { grow(b.lo, b.hi); }
    Aabb aabb() const {
        alignas(16) float l[4], h[4];
        _mm_store_ps(l, lo);
        _mm_store_ps(h, hi);
        return {{l[0], l[1], l[2]}, {h[0], h[1], h[2]}};
    }
};

// Half the surface area, (xy + yz) + zx as Aabb::half_area_float (T = float)
// and Aabb::half_area (T = double, from double extents); non-empty boxes only.
template <class T>
T half_area(const Box4& b) {
    if constexpr (std::is_same_v<T, float>) {
        const __m128 e = _mm_sub_ps(b.hi, b.lo);
        const __m128 p = _mm_mul_ps(e, _mm_shuffle_ps(e, e, _MM_SHUFFLE(3, 0, 2, 1)));  // xy, yz, zx, -
        alignas(16) float v[4];
        _mm_store_ps(v, p);
        return (v[0] + v[1]) + v[2];
    } else {
        alignas(16) float l[4], h[4];
        _mm_store_ps(l, b.lo);
        _mm_store_ps(h, b.hi);
        const double ex = double(h[0]) - double(l[0]), ey = double(h[1]) - double(l[1]),
                     ez = double(h[2]) - double(l[2]);
        return (ex * ey + ey * ez) + ez * ex;
    }
}

struct Bin {
    Box4 box;
    std::uint32_t count = 0;
};

// Bins on the three axes. Up to kMaskBins bins, the non-empty ones are also
// kept as bit masks: the sweep then visits them without scanning the table,
// and clear() resets only them (small nodes touch a few of the 3 x nbins).
// The table is empty between uses.
constexpr int kMaskBins = 64;
struct Bins3 {
    Bin bins[3][kMaxBins];
    std::uint64_t used[3] = {};  // nbins <= kMaskBins: bit b = bin b is not empty
    void clear(int nbins) {
        for (int a = 0; a < 3; ++a) {
            if (nbins <= kMaskBins) {
                for (std::uint64_t m = used[a]; m; m &= m - 1) bins[a][__builtin_ctzll(m)] = Bin{};
            } else {
                for (int b = 0; b < nbins; ++b) bins[a][b] = Bin{};
            }
            used[a] = 0;
        }
    }
};

struct Split {
    int axis = -1;      // -1: no usable split
    int bin = 0;        // primitives with bin index < bin go left
    bool leaf = false;  // the SAH prefers a leaf
};

inline __m128 load_lo(const PrimRef& r) { return _mm_load_ps(&r.lo.x); }
inline __m128 load_hi(const PrimRef& r) { return _mm_load_ps(&r.hi.x); }
inline __m128 load_c(const PrimRef& r) { return _mm_load_ps(&r.c.x); }

struct Binner {
    __m128 cmin, scale, top;  // top = nbins - 1
    int nbins;
    Binner(const Aabb& cbox, int n, const float s[3]) : nbins(n) {
        cmin = _mm_setr_ps(cbox.lo.x, cbox.lo.y, cbox.lo.z, 0.0f);
        scale = _mm_setr_ps(s[0], s[1], s[2], 0.0f);
        top = _mm_set1_ps(float(n - 1));
    }
    // Bin indices on the three axes: min(n - 1, int((c - cmin) * scale)).
    __m128i index(__m128 c) const { return _mm_cvttps_epi32(_mm_min_ps(_mm_mul_ps(_mm_sub_ps(c, cmin), scale), top)); }
};

// Adds one primitive to its bin on each axis (and to the masks of non-empty
// bins when kMasks).
template <bool kMasks>
inline void bin_one(const PrimRef& r, const Binner& binner, Bins3& out, std::uint64_t used[3]) {
    alignas(16) std::int32_t idx[4];
    const __m128 lo = load_lo(r), hi = load_hi(r);
    _mm_store_si128(reinterpret_cast<__m128i*>(idx), binner.index(load_c(r)));
    for (int a = 0; a < 3; ++a) {
        Bin& bin = out.bins[a][idx[a]];
        bin.box.grow(lo, hi);
        bin.count++;
        if constexpr (kMasks) used[a] |= std::uint64_t(1) << (idx[a] & (kMaskBins - 1));  // nbins <= kMaskBins
    }
}

// Merges `from` into `into` and leaves `from` empty.
void merge_bins(Bins3& into, Bins3& from, int nbins) {
    for (int a = 0; a < 3; ++a) {
        for (int b = 0; b < nbins; ++b) {
            into.bins[a][b].box.grow(from.bins[a][b].box);
            into.bins[a][b].count += from.bins[a][b].count;
        }
        into.used[a] |= from.used[a];
    }
    from.clear(nbins);
}

// Ranges this large are binned into two tables, even and odd primitives,
// merged at the end: neighbours (often in the same bin) then do not wait on
// each other's read-modify-write of one bin. The merged bins hold the same
// primitives; a box differs at most in the sign of a zero coordinate, which
// no area comparison sees. They keep no masks: every bin counts as used. An
// empty bin in the sweep leaves the running box and count as they are, so
// its boundary repeats the previous numerator (never strictly smaller) or
// has an empty side (0 * inf = NaN, never smaller): the same split.
constexpr std::uint32_t kTwoTablesMin = 1024;

// Bins refs[begin, end) on all three axes in one pass, into an empty table.
void bin_range(const BuildContext& ctx, std::uint32_t begin, std::uint32_t end, const Binner& binner, Bins3& out) {
    std::uint64_t used[3] = {};
    if (end - begin >= kTwoTablesMin) {
        thread_local Bins3 odd;  // empty between uses
        std::uint32_t i = begin;
        for (; i + 1 < end; i += 2) {
            bin_one<false>(ctx.refs[i], binner, out, used);
            bin_one<false>(ctx.refs[i + 1], binner, odd, used);
        }
        if (i < end) bin_one<false>(ctx.refs[i], binner, out, used);
        const std::uint64_t all = binner.nbins >= 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << binner.nbins) - 1;
        for (int a = 0; a < 3; ++a) odd.used[a] = used[a] = all;
        merge_bins(out, odd, binner.nbins);
    } else {
        for (std::uint32_t i = begin; i < end; ++i) bin_one<true>(ctx.refs[i], binner, out, used);
    }
    for (int a = 0; a < 3; ++a) out.used[a] |= used[a];
}

// Ranges this large are binned by several threads; bins merge exactly
// (min/max and integer counts), so the result does not depend on the count.
constexpr std::uint32_t kParallelBinMin = 128 * 1024;

// The best split so far over all axes: the minimal SAH numerator, first
// axis then first bin boundary on ties (the order of the sweeps).
template <class T>
struct Best {
    T num = std::numeric_limits<T>::infinity();
    int axis = -1, bin = 0;
};

// The SAH sweep over one axis, costs in T (BuildContext::float_costs).
// The minimum needs only the numerator A_L N_L + A_R N_R: the cost is
// Ct + Ci * numerator / A, monotonic in it. Only boundaries between
// non-empty bins give distinct partitions, so the sweep visits the k >= 2
// non-empty bins only, in bin order: box(j), count(j), index(j); the chosen
// split is the first minimal bin boundary, as a sweep over every bin would pick.
template <class T, class BoxAt, class CountAt, class IndexAt>
void sweep_axis(int axis, int k, BoxAt box, CountAt count, IndexAt index, Best<T>& best) {
    T right_area[kMaxBins];
    std::uint32_t right_count[kMaxBins];
    Box4 acc;
    std::uint32_t cnt = 0;
    for (int j = k - 1; j > 0; --j) {
        acc.grow(box(j));
        cnt += count(j);
        right_area[j] = half_area<T>(acc);
        right_count[j] = cnt;
    }
    acc = Box4{};
    cnt = 0;
    for (int j = 1; j < k; ++j) {
        acc.grow(box(j - 1));
        cnt += count(j - 1);
        const T num = half_area<T>(acc) * T(cnt) + right_area[j] * T(right_count[j]);
        // Selects with masks, not branches (the outcome is unpredictable).
        const int keep = int(num < best.num) - 1;    // 0: take the new split, -1: keep the best
        best.num = num < best.num ? num : best.num;  // minss
        best.axis = (best.axis & keep) | (axis & ~keep);
        best.bin = (best.bin & keep) | ((index(j - 1) + 1) & ~keep);
    }
}

// The leaf test of the best split: the SAH cost against the leaf cost.
template <class T>
Split finish(const BuildContext& ctx, const Best<T>& b, const Aabb& node_box, std::uint32_t n) {
    Split best;
    best.axis = b.axis;
    best.bin = b.bin;
    // A flat parent (zero area: collinear or coincident boxes) makes every split cost the same.
    const T parent_area = sah_area<T>(node_box);
    const T ct = T(ctx.opts.traversal_cost), ci = T(ctx.opts.intersection_cost);
    const T cost = parent_area > T(0) ? ct + ci * b.num / parent_area : ct;
    best.leaf = cost >= ci * T(n) && n <= std::uint32_t(ctx.opts.max_leaf_size);
    return best;
}

// The best split over the filled bins.
template <class T>
Split best_split(const BuildContext& ctx, const Bins3& bins, int nbins, const float scale[3], const Aabb& node_box,
                 std::uint32_t n) {
    Best<T> best;
    int used[kMaxBins];
    for (int axis = 0; axis < 3; ++axis) {
        if (scale[axis] == 0.0f) continue;
        const Bin* bn = bins.bins[axis];
        int k = 0;
        if (nbins <= kMaskBins) {
            for (std::uint64_t m = bins.used[axis]; m; m &= m - 1) used[k++] = __builtin_ctzll(m);
        } else {
            for (int b = 0; b < nbins; ++b) {  // branch-free: empty bins are unpredictable in small nodes
                used[k] = b;
                k += bn[b].count != 0;
            }
        }
        if (k < 2) continue;
        sweep_axis<T>(
            axis, k, [&](int j) -> const Box4& { return bn[used[j]].box; }, [&](int j) { return bn[used[j]].count; },
            [&](int j) { return used[j]; }, best);
    }
    return finish(ctx, best, node_box, n);
}

// Two primitives (a third of all nodes): the bins the table would hold
// directly. Every axis that puts them in different bins offers the same
// partition at the same numerator A_a + A_b (float addition commutes), so
// the first such axis wins, as in the sweep; no such axis: no split.
template <class T>
Split best_split_pair(const BuildContext& ctx, std::uint32_t begin, const Binner& binner, const float scale[3],
                      const Aabb& node_box) {
    const PrimRef& p = ctx.refs[begin];
    const PrimRef& q = ctx.refs[begin + 1];
    alignas(16) std::int32_t ip[4], iq[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(ip), binner.index(load_c(p)));
    _mm_store_si128(reinterpret_cast<__m128i*>(iq), binner.index(load_c(q)));
    Best<T> best;
    for (int axis = 0; axis < 3; ++axis) {
        if (scale[axis] == 0.0f || ip[axis] == iq[axis]) continue;
        const bool p_low = ip[axis] < iq[axis];
        Box4 low, high;
        low.grow(load_lo(p_low ? p : q), load_hi(p_low ? p : q));
        high.grow(load_lo(p_low ? q : p), load_hi(p_low ? q : p));
        best.num = half_area<T>(low) * T(1) + half_area<T>(high) * T(1);
        best.axis = axis;
        best.bin = (p_low ? ip[axis] : iq[axis]) + 1;
        break;
    }
    return finish(ctx, best, node_box, 2);
}

// Bin scales per axis: nbins / centroid extent, 0 for a flat (or non-finite) axis.
Binner make_binner(const Aabb& centroid_box, int nbins, float scale[3]) {
    for (int a = 0; a < 3; ++a) {
        const float extent = centroid_box.hi[a] - centroid_box.lo[a];
        scale[a] = extent > 0.0f ? float(nbins) / extent : 0.0f;
        if (extent == std::numeric_limits<float>::infinity())  // finite centroids more than FLT_MAX apart
            scale[a] = float(double(nbins) / (double(centroid_box.hi[a]) - double(centroid_box.lo[a])));
        if (!std::isfinite(scale[a])) scale[a] = 0.0f;
    }
    return Binner(centroid_box, nbins, scale);
}

// Bins refs[begin, end), on several threads when the range is large. The
// result is in a thread_local table (no allocation per node).
Bins3& fill_bins(BuildContext& ctx, std::uint32_t begin, std::uint32_t end, const Binner& binner) {
    thread_local Bins3 tl_bins;  // empty between uses (split_binned_sah clears it)
    Bins3* bins = &tl_bins;
    const std::uint32_t n = end - begin;
    // Helpers take spare build threads (BuildContext::spare_threads), so
    // subtrees already running on every thread are not oversubscribed.
    struct Helpers {
        std::atomic<int>& spare;
        int taken = 0;
        ~Helpers() {
            if (taken) spare.fetch_add(taken);  // no atomic write per node: the count's cache line stays shared
        }
    } helpers{ctx.spare_threads};
    if (n >= kParallelBinMin) {
        const int want = std::min(ctx.opts.threads, 8) - 1;
        for (int s = ctx.spare_threads.load(); helpers.taken < want && s > 0;)
            if (ctx.spare_threads.compare_exchange_weak(s, s - 1)) ++helpers.taken, s = ctx.spare_threads.load();
    }
    const int workers = 1 + helpers.taken;
    if (workers <= 1) {
        bin_range(ctx, begin, end, binner, *bins);
        return *bins;
    }
    // One task per chunk (run_tasks: the host executor's, or threads of
    // ours), each into a table of its own: while this thread waits, a host's
    // work-stealing pool may run another subtree's build on it, which uses
    // (and leaves empty) this thread's thread_local table; it is filled only
    // after the wait.
    std::vector<std::unique_ptr<Bins3>> parts(static_cast<std::size_t>(workers));
    for (auto& part : parts) part = std::make_unique<Bins3>();
    const std::uint32_t chunk = (n + std::uint32_t(workers) - 1) / std::uint32_t(workers);
    run_tasks(std::size_t(workers), [&](std::size_t w) {
        const std::uint32_t b = std::min(end, begin + chunk * std::uint32_t(w));
        const std::uint32_t e = std::min(end, b + chunk);
        bin_range(ctx, b, e, binner, *parts[w]);
    });
    for (const auto& part : parts) merge_bins(*bins, *part, binner.nbins);
    return *bins;
}

// Partitions refs[begin, end) in place by the split's bin boundary, gathering
// both children's bounds on the way: a two-sided scan (left from the front,
// right from the back, swapping the pairs it finds). The left child's bounds
// grow over its positions in ascending order, the right child's in
// descending order.
SplitResult partition_scan(BuildContext& ctx, std::uint32_t begin, std::uint32_t end, const Binner& binner,
                           const Split& best) {
    alignas(16) std::int32_t idx[4];
    auto goes_left = [&](const PrimRef& p) {
        _mm_store_si128(reinterpret_cast<__m128i*>(idx), binner.index(load_c(p)));
        return idx[best.axis] < best.bin;
    };
    Box4 lbox, lcbox, rbox, rcbox;
    auto add_left = [&](const PrimRef& p) {
        lbox.grow(load_lo(p), load_hi(p));
        const __m128 c = load_c(p);
        lcbox.grow(c, c);
    };
    auto add_right = [&](const PrimRef& p) {
        rbox.grow(load_lo(p), load_hi(p));
        const __m128 c = load_c(p);
        rcbox.grow(c, c);
    };
    std::uint32_t i = begin, j = end;  // [begin, i) left, [j, end) right
    PrimRef* refs = ctx.refs.data();
    for (;;) {
        while (i < j && goes_left(refs[i])) add_left(refs[i++]);
        while (i < j && !goes_left(refs[j - 1])) add_right(refs[--j]);
        if (i >= j) break;
        std::swap(refs[i], refs[j - 1]);
        add_left(refs[i++]);
        add_right(refs[--j]);
    }
    SplitResult r;
    r.mid = i;
    r.found = true;
    r.has_bounds = true;
    r.left = {lbox.aabb(), lcbox.aabb()};
    r.right = {rbox.aabb(), rcbox.aabb()};
    return r;
}

// Ranges up to this size are partitioned without a branch per primitive
// (which side a primitive goes to is unpredictable); larger ones are
// memory-bound and take the scan.
constexpr std::uint32_t kFlagPartitionMax = 16 * 1024;  // 48 bytes each: within L2

// The same permutation and bounds as partition_scan, without its
// data-dependent branches: the scan swaps the k-th right-goer from the front
// with the k-th left-goer from the back, and stops where they cross, at
// begin + (number of left-goers). So: flags, then both lists of positions
// (appended without branches), the swaps, and the bounds in the scan's order.
SplitResult partition_flags(BuildContext& ctx, std::uint32_t begin, std::uint32_t end, const Binner& binner,
                            const Split& best) {
    const std::uint32_t n = end - begin;
    PrimRef* refs = ctx.refs.data() + begin;
    thread_local std::vector<std::uint8_t> left_buf;  // per thread: no allocation per node
    thread_local std::vector<std::uint32_t> holes_buf, movers_buf;
    if (left_buf.size() < n) {
        left_buf.resize(kFlagPartitionMax);
        holes_buf.resize(kFlagPartitionMax);
        movers_buf.resize(kFlagPartitionMax);
    }
    std::uint8_t* left = left_buf.data();
    std::uint32_t *holes = holes_buf.data(), *movers = movers_buf.data();
    alignas(16) std::int32_t idx[4];
    std::uint32_t nl = 0;
    for (std::uint32_t i = 0; i < n; ++i) {
        _mm_store_si128(reinterpret_cast<__m128i*>(idx), binner.index(load_c(refs[i])));
        left[i] = idx[best.axis] < best.bin;
        nl += left[i];
    }
    std::uint32_t h = 0, m = 0;
    for (std::uint32_t i = 0; i < nl; ++i) {  // right-goers in the left part, front to back
        holes[h] = i;
        h += 1u - left[i];
    }
    for (std::uint32_t i = n; i-- > nl;) {  // left-goers in the right part, back to front
        movers[m] = i;
        m += left[i];
    }
    for (std::uint32_t k = 0; k < h; ++k) std::swap(refs[holes[k]], refs[movers[k]]);
    Box4 lbox, lcbox, rbox, rcbox;
    for (std::uint32_t i = 0; i < nl; ++i) {
        lbox.grow(load_lo(refs[i]), load_hi(refs[i]));
        const __m128 c = load_c(refs[i]);
        lcbox.grow(c, c);
    }
    for (std::uint32_t i = n; i-- > nl;) {
        rbox.grow(load_lo(refs[i]), load_hi(refs[i]));
        const __m128 c = load_c(refs[i]);
        rcbox.grow(c, c);
    }
    SplitResult r;
    r.mid = begin + nl;
    r.found = true;
    r.has_bounds = true;
    r.left = {lbox.aabb(), lcbox.aabb()};
    r.right = {rbox.aabb(), rcbox.aabb()};
    return r;
}

SplitResult partition(BuildContext& ctx, std::uint32_t begin, std::uint32_t end, const Binner& binner,
                      const Split& best) {
    return end - begin <= kFlagPartitionMax ? partition_flags(ctx, begin, end, binner, best)
                                            : partition_scan(ctx, begin, end, binner, best);
}

}  // namespace

SplitResult split_binned_sah(BuildContext& ctx, std::uint32_t begin, std::uint32_t end, const Aabb& node_box,
                             const Aabb& centroid_box, int /*depth*/) {
    const int nbins = std::clamp(ctx.opts.bins, 2, kMaxBins);
    const std::uint32_t n = end - begin;
    float scale[3];
    const Binner binner = make_binner(centroid_box, nbins, scale);
    Split best;
    if (n == 2) {
        best = ctx.float_costs ? best_split_pair<float>(ctx, begin, binner, scale, node_box)
                               : best_split_pair<double>(ctx, begin, binner, scale, node_box);
    } else {
        Bins3& bins = fill_bins(ctx, begin, end, binner);
        best = ctx.float_costs ? best_split<float>(ctx, bins, nbins, scale, node_box, n)
                               : best_split<double>(ctx, bins, nbins, scale, node_box, n);
        bins.clear(nbins);
    }
    SplitResult r;
    if (best.axis < 0) return r;  // no usable split: the caller falls back
    r.make_leaf = best.leaf;
    if (r.make_leaf) return r;
    return partition(ctx, begin, end, binner, best);
}

}  // namespace simdbvh::detail
