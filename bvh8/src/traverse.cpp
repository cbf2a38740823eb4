// BVH8 batched entry points: the only place that chooses an ISA for BVH8.
#include "simdbvh/kernels/error.h"
#include "simdbvh/kernels/parallel.h"
#include "traverse.h"

namespace simdbvh {

namespace {

using TraceFn = void (*)(const Bvh8&, std::span<const Ray>, std::span<Hit>, const TraceOptions&);

template <bool kAnyHit>
void run(const Bvh8& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& o, Isa isa) {
    if (hits.size() < rays.size()) throw Error("hits span is smaller than rays span");
    require(isa);
    TraceFn fn = nullptr;
    switch (isa) {
    case Isa::avx512: fn = kAnyHit ? &bvh8::avx512::occluded : &bvh8::avx512::intersect; break;
    case Isa::avx2: fn = kAnyHit ? &bvh8::avx2::occluded : &bvh8::avx2::intersect; break;
    case Isa::scalar: fn = kAnyHit ? &bvh8::scalar::occluded : &bvh8::scalar::intersect; break;
    }
    if (!fn) throw Error("unknown ISA");
    if (o.stats || o.threads <= 1) return fn(bvh, rays, hits, o);  // stats: one thread (unsynchronized counters)
    parallel_for(rays.size(), o.threads, [&](std::size_t b, std::size_t e) {
        fn(bvh, rays.subspan(b, e - b), hits.subspan(b, e - b), o);
    });
}

}  // namespace

void intersect(const Bvh8& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& o, Isa isa) {
    run<false>(bvh, rays, hits, o, isa);
}
void occluded(const Bvh8& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& o, Isa isa) {
    run<true>(bvh, rays, hits, o, isa);
}
Hit intersect(const Bvh8& bvh, const Ray& ray, const TraceOptions& o, Isa isa) {
    Hit h;
    run<false>(bvh, std::span<const Ray>(&ray, 1), std::span<Hit>(&h, 1), o, isa);
    return h;
}
Hit occluded(const Bvh8& bvh, const Ray& ray, const TraceOptions& o, Isa isa) {
    Hit h;
    run<true>(bvh, std::span<const Ray>(&ray, 1), std::span<Hit>(&h, 1), o, isa);
    return h;
}

}  // namespace simdbvh
