// Wide BVH batched entry points (N = 4, 8, 16): the only place that chooses
// an ISA for them (explicitly, or by speed: isa_choice.h).
#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "simdbvh/bvh8/batch_order.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/kernels/parallel.h"
#include "isa_choice.h"
#include "ray_order.h"
#include "scratch_pool.h"
#include "traverse.h"

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

// The batch traced in its sorted order (ray_order.h), segment by segment:
// blocks of the sorted rays gathered, traced (on o.threads threads, a block
// per chunk) and their hits scattered back to the caller's positions.
template <int N>
void trace_sorted(TraceFn<N> fn, const BvhN<N>& bvh, std::span<const Ray> rays, std::span<Hit> hits,
                  const TraceOptions& o) {
    using namespace bvh8::detail;
    auto& sorted_pool = detail::ScratchPool<Sorted>::of_this_thread();
    auto& gathered_pool = detail::ScratchPool<Gathered>::of_this_thread();
    std::unique_ptr<Sorted> sorted = sorted_pool.take();
    std::vector<std::uint64_t>& order = sorted->order;
    TraceOptions one = o;
    one.threads = 1;
    for (std::size_t s = 0; s < rays.size(); s += kReorderSegment) {
        const std::size_t n = std::min(kReorderSegment, rays.size() - s);
        const std::span<const Ray> seg = rays.subspan(s, n);
        const std::span<Hit> out = hits.subspan(s, n);
        sort_rays(seg, bvh.bounds(), order, sorted->work);
        auto blocks = [&](std::size_t b, std::size_t e) {
            std::unique_ptr<Gathered> taken = gathered_pool.take();
            Gathered& g = *taken;
            for (std::size_t k = b; k < e; ++k) {
                const std::size_t lo = k * kReorderBlock, hi = std::min(n, lo + kReorderBlock);
                g.rays.resize(hi - lo);
                g.hits.resize(hi - lo);
                for (std::size_t i = lo; i < hi; ++i) g.rays[i - lo] = seg[order_index(order[i])];
                fn(bvh, g.rays, g.hits, one);
                for (std::size_t i = lo; i < hi; ++i) out[order_index(order[i])] = g.hits[i - lo];
            }
            gathered_pool.give(std::move(taken));
        };
        const std::size_t count = (n + kReorderBlock - 1) / kReorderBlock;
        if (o.stats || o.threads <= 1) blocks(0, count);
        else parallel_for(count, o.threads, blocks, {.grain = 1});
    }
    sorted_pool.give(std::move(sorted));
}

template <int N, bool kAnyHit>
void run(const BvhN<N>& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& o, Isa isa) {
    if (hits.size() < rays.size()) throw Error("hits span is smaller than rays span");
    if (o.in_flight != 0 && o.in_flight != 1 && o.in_flight != bvh8::detail::kInFlight)
        throw Error("TraceOptions::in_flight must be 0 (by tree size), 1 or " +
                    std::to_string(bvh8::detail::kInFlight) + ", got " + std::to_string(o.in_flight));
    require(isa);
    TraceFn<N> fn = nullptr;
    switch (isa) {
    case Isa::avx512: fn = entry<bvh8::avx512::Kernels, N, kAnyHit>(); break;
    case Isa::avx2: fn = entry<bvh8::avx2::Kernels, N, kAnyHit>(); break;
    case Isa::scalar: fn = entry<bvh8::scalar::Kernels, N, kAnyHit>(); break;
    }
    if (!fn) throw Error("unknown ISA");
    if (reordered(rays, bvh.bounds(), o.reorder)) return trace_sorted<N>(fn, bvh, rays, hits, o);
    if (o.stats || o.threads <= 1) return fn(bvh, rays, hits, o);  // stats: one thread (unsynchronized counters)
    parallel_for(rays.size(), o.threads, [&](std::size_t b, std::size_t e) {
        fn(bvh, rays.subspan(b, e - b), hits.subspan(b, e - b), o);
    });
}

// Without an explicit ISA: the calibrated choice (isa_choice.h), the
// calibration itself tracing the batch's leading rays with every candidate.
template <int N, bool kAnyHit>
void run_auto(const BvhN<N>& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& o) {
    if (hits.size() < rays.size()) throw Error("hits span is smaller than rays span");
    const bool calibrated =
        !o.stats && bvh8::detail::calibrate(N, kAnyHit, rays.size(), [&](Isa isa, std::size_t b, std::size_t e) {
            TraceOptions one = o;
            one.threads = 1;
            run<N, kAnyHit>(bvh, rays.subspan(b, e - b), hits.subspan(b, e - b), one, isa);
        });
    const Isa isa = bvh8::detail::current_isa(N, kAnyHit);
    // A sorted batch is sorted whole (the calibration's rays traced again: the
    // same hits); sorted in the pieces between the calibration's chunks, each
    // a fifth as dense, the dragon's 2^20 bounces ran 3.55 Mrays/s instead of 4.05
    // (BVH16, `simdbvh trace`, whose one batch calibrates).
    if (!calibrated || reordered(rays, bvh.bounds(), o.reorder)) return run<N, kAnyHit>(bvh, rays, hits, o, isa);
    std::size_t b = 0;  // the rays between the calibration's chunks
    for (std::size_t c = 0; c <= bvh8::detail::kCalibrationChunks; ++c) {
        const std::size_t e =
            c < bvh8::detail::kCalibrationChunks ? bvh8::detail::calibration_chunk(c, rays.size()).begin : rays.size();
        if (e > b) run<N, kAnyHit>(bvh, rays.subspan(b, e - b), hits.subspan(b, e - b), o, isa);
        if (c < bvh8::detail::kCalibrationChunks) b = bvh8::detail::calibration_chunk(c, rays.size()).end;
    }
}

}  // namespace

template <int N>
void intersect(const BvhN<N>& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& o) {
    run_auto<N, false>(bvh, rays, hits, o);
}
template <int N>
void occluded(const BvhN<N>& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& o) {
    run_auto<N, true>(bvh, rays, hits, o);
}
template <int N>
Hit intersect(const BvhN<N>& bvh, const Ray& ray, const TraceOptions& o) {
    return intersect<N>(bvh, ray, o, bvh8::detail::current_isa(N, false));
}
template <int N>
Hit occluded(const BvhN<N>& bvh, const Ray& ray, const TraceOptions& o) {
    return occluded<N>(bvh, ray, o, bvh8::detail::current_isa(N, true));
}

template <int N>
void intersect(const BvhN<N>& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& o, Isa isa) {
    run<N, false>(bvh, rays, hits, o, isa);
}
template <int N>
void occluded(const BvhN<N>& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& o, Isa isa) {
    run<N, true>(bvh, rays, hits, o, isa);
}
template <int N>
Hit intersect(const BvhN<N>& bvh, const Ray& ray, const TraceOptions& o, Isa isa) {
    Hit h;
    run<N, false>(bvh, std::span<const Ray>(&ray, 1), std::span<Hit>(&h, 1), o, isa);
    return h;
}
template <int N>
Hit occluded(const BvhN<N>& bvh, const Ray& ray, const TraceOptions& o, Isa isa) {
    Hit h;
    run<N, true>(bvh, std::span<const Ray>(&ray, 1), std::span<Hit>(&h, 1), o, isa);
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

#define SIMDBVH_WIDTH(N)                                                                                          \
    template bool traces_sorted<N>(const BvhN<N>&, std::span<const Ray>, const TraceOptions&);                  \
    template bool traces_sorted<N>(const BvhN<N>&, std::size_t, const std::function<Ray(std::size_t)>&,         \
                                   const TraceOptions&);                                                        \
    template void intersect<N>(const BvhN<N>&, std::span<const Ray>, std::span<Hit>, const TraceOptions&, Isa); \
    template void occluded<N>(const BvhN<N>&, std::span<const Ray>, std::span<Hit>, const TraceOptions&, Isa);  \
    template Hit intersect<N>(const BvhN<N>&, const Ray&, const TraceOptions&, Isa);                            \
    template Hit occluded<N>(const BvhN<N>&, const Ray&, const TraceOptions&, Isa);                             \
    template void intersect<N>(const BvhN<N>&, std::span<const Ray>, std::span<Hit>, const TraceOptions&);      \
    template void occluded<N>(const BvhN<N>&, std::span<const Ray>, std::span<Hit>, const TraceOptions&);       \
    template Hit intersect<N>(const BvhN<N>&, const Ray&, const TraceOptions&);                                 \
    template Hit occluded<N>(const BvhN<N>&, const Ray&, const TraceOptions&);
SIMDBVH_WIDTH(4)
SIMDBVH_WIDTH(8)
SIMDBVH_WIDTH(16)
#undef SIMDBVH_WIDTH

}  // namespace simdbvh
