// BVH8 batched entry points: the only place that chooses an ISA for BVH8.
#include "simdbvh/kernels/error.h"
#include "traverse.h"

namespace simdbvh {

namespace {

template <bool kAnyHit>
void run(const Bvh8& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& o, Isa isa) {
    if (hits.size() < rays.size()) throw Error("hits span is smaller than rays span");
    require(isa);
    switch (isa) {
    case Isa::avx512: return kAnyHit ? bvh8::avx512::occluded(bvh, rays, hits, o) : bvh8::avx512::intersect(bvh, rays, hits, o);
    case Isa::avx2: return kAnyHit ? bvh8::avx2::occluded(bvh, rays, hits, o) : bvh8::avx2::intersect(bvh, rays, hits, o);
    case Isa::scalar: return kAnyHit ? bvh8::scalar::occluded(bvh, rays, hits, o) : bvh8::scalar::intersect(bvh, rays, hits, o);
    }
    throw Error("unknown ISA");
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
