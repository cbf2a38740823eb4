// Accel: the chosen method behind one variant; one dispatch per batch.
#include "simdbvh/accel/accel.h"

#include <chrono>

#include "simdbvh/kernels/error.h"
#include "simdbvh/platform/parallel.h"

namespace simdbvh {

namespace {

// The tree BvhN<N>::build(mesh, build, wide) builds, on the Accel's threads:
// its BVH2 topology with the wide intersection cost, collapsed and packed
// without a BVH2 (not the BVH2 of BuildOptions' intersection cost collapsed:
// a deeper tree, and on the dragon 351-370 ms against 260 for the width's own).
template <int N>
BvhN<N> build_wide(const Mesh& mesh, const AccelOptions& o) {
    WideOptions w = o.wide;
    w.threads = o.threads;
    return BvhN<N>::build(mesh, o.build, w);
}

}  // namespace

Accel Accel::build(const Mesh& mesh, std::size_t expected_rays, const AccelOptions& opts) {
    const CostModel& model = opts.model ? *opts.model : cost_model(opts.isa);
    return build(mesh, choose(model, mesh.size(), expected_rays, opts.threads).method, expected_rays, opts);
}

Accel Accel::build(const Mesh& mesh, AccelMethod method, std::size_t expected_rays, const AccelOptions& opts) {
    require(opts.isa);
    const auto t0 = std::chrono::steady_clock::now();
    Accel a;
    a.choice_ = choose(opts.model ? *opts.model : cost_model(opts.isa), mesh.size(), expected_rays, opts.threads);
    a.choice_.method = method;
    a.isa_ = opts.isa;
    AccelOptions o = opts;
    o.build.threads = opts.threads;
    switch (method) {
    case AccelMethod::brute:
        validate(mesh);
        a.impl_ = Brute{mesh};
        break;
    case AccelMethod::brute8: a.impl_ = BruteForce8::build(mesh); break;
    case AccelMethod::bvh2: a.impl_ = Bvh2::build(mesh, o.build); break;
    case AccelMethod::bvh4: a.impl_ = build_wide<4>(mesh, o); break;
    case AccelMethod::bvh8: a.impl_ = build_wide<8>(mesh, o); break;
    case AccelMethod::bvh16: a.impl_ = build_wide<16>(mesh, o); break;
    }
    a.build_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return a;
}

namespace {

template <bool Any>
void trace(const Accel& a, const auto& impl, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& o) {
    using T = std::decay_t<decltype(impl)>;
    if constexpr (requires { impl.mesh; }) {
        simdbvh::detail::check_size(hits.size(), rays.size(), "hits");
        parallel_for(
            rays.size(), o.threads,
            [&](std::size_t b, std::size_t e) {
                for (std::size_t i = b; i < e; ++i)
                    hits[i] = Any ? brute_force_occluded(impl.mesh, rays[i], o.test)
                                  : brute_force_intersect(impl.mesh, rays[i], o.test);
            },
            options_for_cost(impl.mesh.size()));
    } else if constexpr (std::is_same_v<T, Bvh2>) {
        Any ? occluded(impl, rays, hits, o) : intersect(impl, rays, hits, o);
    } else {  // the brute force and the wide trees: the caller's ISA, else the Accel's
        TraceOptions with = o;
        with.isa = o.isa.value_or(a.isa());
        Any ? occluded(impl, rays, hits, with) : intersect(impl, rays, hits, with);
    }
}

}  // namespace

void intersect(const Accel& a, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& opts) {
    std::visit([&](const auto& impl) { trace<false>(a, impl, rays, hits, opts); }, a.impl_);
}

void occluded(const Accel& a, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& opts) {
    std::visit([&](const auto& impl) { trace<true>(a, impl, rays, hits, opts); }, a.impl_);
}

}  // namespace simdbvh
