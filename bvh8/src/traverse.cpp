// Wide BVH batched entry points (N = 4, 8, 16): the only place that chooses
// an ISA for them (explicitly, or by speed: isa_choice.h).
#include <algorithm>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "simdbvh/bvh8/batch_order.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/platform/parallel.h"
#include "simdbvh/bvh8/internal/isa_choice.h"
#include "simdbvh/bvh8/internal/ray_order.h"
#include "simdbvh/platform/internal/scratch_pool.h"
#include "simdbvh/bvh8/internal/traverse.h"

namespace simdbvh {

namespace {

template <int N>
using TraceFn = void (*)(const BvhN<N>&, std::span<const Ray>, std::span<Hit>, const TraceOptions&);

template <class K, int N, bool kAnyHit>
constexpr TraceFn<N> entry() {
    return kAnyHit ? &bvh8::Traversal<K, N>::occluded : &bvh8::Traversal<K, N>::intersect;
}

// A block of the sorted batch, gathered (kReorderBlock x 48 bytes), and a
// segment's sorted order with the sort's scratch (16 bytes per ray of the
// largest segment, at most 16 MiB): kept from call to call in the calling
// thread's pools (scratch_pool.h; made per call they were page faults on
// every call, 11% of a 262,144-ray batch's time).
struct Gathered {
    std::vector<Ray> rays;
    std::vector<Hit> hits;
};
struct Sorted {
    std::vector<std::uint64_t> order, work;
};

// Whether a batch of n rays is traced sorted; scattered() runs ray_order.h's rule on it.
template <class Scattered>
bool reordered(std::size_t n, Reorder r, const Scattered& scattered) {
    if (r == Reorder::on) return n > 1;
    return r == Reorder::automatic && n >= bvh8::detail::kReorderMinRays && scattered();
}
bool reordered(std::span<const Ray> rays, const Aabb& bounds, Reorder r) {
    return reordered(rays.size(), r, [&] { return bvh8::detail::scattered(rays, bounds); });
}

template <int N, bool kAnyHit>
TraceFn<N> fn_of(Isa isa) {
    return bvh8::with_kernels(isa, [&]<class K>() { return entry<K, N, kAnyHit>(); });
}

// [0, n) without the calibration's groups (none: all of it), in pieces of at
// most `piece` rays starting where a group ends (the groups start and end at
// multiples of 32: the pieces keep the streams of 32 of the batch).
std::vector<bvh8::detail::Range> pieces(std::size_t n, const std::vector<bvh8::detail::Range>& groups,
                                        std::size_t piece) {
    std::vector<bvh8::detail::Range> out;
    auto add = [&](std::size_t b, std::size_t e) {
        for (; b < e; b += piece) out.push_back({b, std::min(e, b + piece)});
    };
    std::size_t at = 0;
    for (const bvh8::detail::Range& g : groups) {
        add(at, g.begin);
        at = g.end;
    }
    add(at, n);
    return out;
}

// The batch traced in its sorted order (ray_order.h), segment by segment:
// blocks of the sorted rays gathered, traced (on o.threads threads, a block
// per chunk) and their hits scattered back to the caller's positions. With a
// calibration (cal: claimed), its groups are positions of the first
// segment's sorted order, traced by the calibration as one more chunk (each
// ray once, as it is traced), and every block with the ISA of the moment
// (current_isa); without, every block with `isa`.
template <int N, bool kAnyHit>
void trace_sorted(const BvhN<N>& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& o, Isa isa,
                  bvh8::detail::Calibration* cal) {
    using namespace bvh8::detail;
    auto& sorted_pool = detail::ScratchPool<Sorted>::of_this_thread();
    auto& gathered_pool = detail::ScratchPool<Gathered>::of_this_thread();
    std::unique_ptr<Sorted> sorted = sorted_pool.take();
    std::vector<std::uint64_t>& order = sorted->order;
    TraceOptions one = o;
    one.threads = 1;
    const TraceFn<N> fixed = cal ? nullptr : fn_of<N, kAnyHit>(isa);
    for (std::size_t s = 0; s < rays.size(); s += kReorderSegment) {
        const std::size_t n = std::min(kReorderSegment, rays.size() - s);
        const std::span<const Ray> seg = rays.subspan(s, n);
        const std::span<Hit> out = hits.subspan(s, n);
        sort_rays(seg, bvh.bounds(), order, sorted->work);
        // Sorted positions [lo, hi) gathered, traced with fn, scattered back.
        auto trace = [&](Gathered& g, TraceFn<N> fn, std::size_t lo, std::size_t hi) {
            g.rays.resize(hi - lo);
            g.hits.resize(hi - lo);
            for (std::size_t i = lo; i < hi; ++i) g.rays[i - lo] = seg[order_index(order[i])];
            fn(bvh, g.rays, g.hits, one);
            for (std::size_t i = lo; i < hi; ++i) out[order_index(order[i])] = g.hits[i - lo];
        };
        const bool calibrating = cal && s == 0;
        const std::vector<Range> items = pieces(n, calibrating ? cal->groups() : std::vector<Range>{}, kReorderBlock);
        auto blocks = [&](std::size_t b, std::size_t e) {
            std::unique_ptr<Gathered> taken = gathered_pool.take();
            Gathered& g = *taken;
            for (std::size_t k = b; k < e; ++k) {
                if (calibrating && k == 0) {
                    cal->run([&](Isa i, std::size_t lo, std::size_t hi) { trace(g, fn_of<N, kAnyHit>(i), lo, hi); });
                    continue;
                }
                const Range r = items[k - (calibrating ? 1 : 0)];
                trace(g, cal ? fn_of<N, kAnyHit>(current_isa(N, kAnyHit)) : fixed, r.begin, r.end);
            }
            gathered_pool.give(std::move(taken));
        };
        // The calibration first (then one thread traces the rest with its
        // choice; with more, the others trace meanwhile).
        const std::size_t count = items.size() + (calibrating ? 1 : 0);
        if (o.stats || o.threads <= 1) blocks(0, count);
        else parallel_for(count, o.threads, blocks, {.grain = 1});
    }
    sorted_pool.give(std::move(sorted));
}

void check(std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& o) {
    simdbvh::detail::check_size(hits.size(), rays.size(), "hits");
    if (o.in_flight != 0 && o.in_flight != 1 && o.in_flight != bvh8::detail::kInFlight)
        throw Error("TraceOptions::in_flight must be 0 (by tree size), 1 or " +
                    std::to_string(bvh8::detail::kInFlight) + ", got " + std::to_string(o.in_flight));
}

// `sorted`: reordered() of the batch, decided by the caller.
template <int N, bool kAnyHit>
void run(const BvhN<N>& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& o, Isa isa,
         bool sorted) {
    const TraceFn<N> fn = fn_of<N, kAnyHit>(isa);
    if (sorted) return trace_sorted<N, kAnyHit>(bvh, rays, hits, o, isa, nullptr);
    if (o.stats || o.threads <= 1) return fn(bvh, rays, hits, o);  // stats: one thread (unsynchronized counters)
    parallel_for(rays.size(), o.threads,
                 [&](std::size_t b, std::size_t e) { fn(bvh, rays.subspan(b, e - b), hits.subspan(b, e - b), o); });
}

template <int N, bool kAnyHit>
void run(const BvhN<N>& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& o, Isa isa) {
    check(rays, hits, o);
    require(isa);
    run<N, kAnyHit>(bvh, rays, hits, o, isa, reordered(rays, bvh.bounds(), o.reorder));
}

// Without an explicit ISA: the calibrated choice (isa_choice.h). The batch
// that calibrates traces the calibration's rays as it times them (each once,
// by one candidate: hits never depend on the ISA) and the rays around them
// in the same parallel call, the calibration one of its chunks: on two
// threads the other thread traces meanwhile (with the best detected ISA until
// the choice is stored). A sorted batch calibrates on its sorted order (the
// first segment's), inside trace_sorted.
template <int N, bool kAnyHit>
void run_auto(const BvhN<N>& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& o) {
    check(rays, hits, o);
    const bool sorted = reordered(rays, bvh.bounds(), o.reorder);
    std::optional<bvh8::detail::Calibration> cal;
    if (!o.stats) cal.emplace(N, kAnyHit, sorted ? std::min(rays.size(), bvh8::detail::kReorderSegment) : rays.size());
    if (!cal || !*cal) return run<N, kAnyHit>(bvh, rays, hits, o, bvh8::detail::current_isa(N, kAnyHit), sorted);
    if (sorted) return trace_sorted<N, kAnyHit>(bvh, rays, hits, o, Isa::scalar, &*cal);
    // The rays around the calibration's groups, whole on one thread, on more in
    // pieces of parallel_for's default grain (as with an ISA given).
    TraceOptions one = o;
    one.threads = 1;
    const std::vector<bvh8::detail::Range> items =
        pieces(rays.size(), cal->groups(), o.threads > 1 ? ParallelOptions{}.grain : rays.size());
    auto trace = [&](Isa isa, std::size_t b, std::size_t e) {
        fn_of<N, kAnyHit>(isa)(bvh, rays.subspan(b, e - b), hits.subspan(b, e - b), one);
    };
    auto body = [&](std::size_t b, std::size_t e) {
        for (std::size_t k = b; k < e; ++k) {
            if (k == 0) cal->run(trace);
            else trace(bvh8::detail::current_isa(N, kAnyHit), items[k - 1].begin, items[k - 1].end);
        }
    };
    if (o.threads <= 1) body(0, items.size() + 1);
    else parallel_for(items.size() + 1, o.threads, body, {.grain = 1});
}

}  // namespace

template <int N>
void intersect(const BvhN<N>& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& o) {
    if (o.isa) return run<N, false>(bvh, rays, hits, o, *o.isa);
    run_auto<N, false>(bvh, rays, hits, o);
}
template <int N>
void occluded(const BvhN<N>& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& o) {
    if (o.isa) return run<N, true>(bvh, rays, hits, o, *o.isa);
    run_auto<N, true>(bvh, rays, hits, o);
}
// One ray: the given ISA, else the current choice (a single ray never calibrates).
template <int N>
Hit intersect(const BvhN<N>& bvh, const Ray& ray, const TraceOptions& o) {
    Hit h;
    run<N, false>(bvh, std::span<const Ray>(&ray, 1), std::span<Hit>(&h, 1), o,
                  o.isa.value_or(bvh8::detail::current_isa(N, false)));
    return h;
}
template <int N>
Hit occluded(const BvhN<N>& bvh, const Ray& ray, const TraceOptions& o) {
    Hit h;
    run<N, true>(bvh, std::span<const Ray>(&ray, 1), std::span<Hit>(&h, 1), o,
                 o.isa.value_or(bvh8::detail::current_isa(N, true)));
    return h;
}

template <int N>
bool traces_sorted(const BvhN<N>& bvh, std::span<const Ray> rays, const TraceOptions& o) {
    return reordered(rays, bvh.bounds(), o.reorder);
}
template <int N>
bool traces_sorted(const BvhN<N>& bvh, std::size_t n, const std::function<Ray(std::size_t)>& ray_at,
                   const TraceOptions& o) {
    return reordered(n, o.reorder, [&] { return bvh8::detail::scattered(n, ray_at, bvh.bounds()); });
}

#define SIMDBVH_WIDTH(N)                                                                                   \
    template bool traces_sorted<N>(const BvhN<N>&, std::span<const Ray>, const TraceOptions&);             \
    template bool traces_sorted<N>(const BvhN<N>&, std::size_t, const std::function<Ray(std::size_t)>&,    \
                                   const TraceOptions&);                                                   \
    template void intersect<N>(const BvhN<N>&, std::span<const Ray>, std::span<Hit>, const TraceOptions&); \
    template void occluded<N>(const BvhN<N>&, std::span<const Ray>, std::span<Hit>, const TraceOptions&);  \
    template Hit intersect<N>(const BvhN<N>&, const Ray&, const TraceOptions&);                            \
    template Hit occluded<N>(const BvhN<N>&, const Ray&, const TraceOptions&);
SIMDBVH_WIDTH(4)
SIMDBVH_WIDTH(8)
SIMDBVH_WIDTH(16)
#undef SIMDBVH_WIDTH

}  // namespace simdbvh
