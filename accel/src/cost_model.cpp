// The cost model's formula and the choice (the coefficients: cost_model_fit.cpp).
#include "simdbvh/accel/cost_model.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "simdbvh/platform/build_threads.h"
#include "simdbvh/kernels/soa.h"
#include "simdbvh/platform/topology.h"
#include "simdbvh/kernels/mesh.h"

namespace simdbvh {

namespace {
// The error of the wide widths' fitted build terms relative to each other, as
// a fraction of BVH8's build (choose()): 5.7% and 7.7% measured, rounded up.
constexpr double kWidthBuildError = 0.08;
constexpr std::string_view kNames[kAccelMethodCount] = {"brute", "brute8", "bvh2", "bvh4", "bvh8", "bvh16"};
}  // namespace

std::string_view name(AccelMethod m) { return kNames[std::size_t(m)]; }

std::optional<AccelMethod> parse_accel_method(std::string_view s) {
    for (AccelMethod m : kAccelMethods)
        if (name(m) == s) return m;
    return std::nullopt;
}

bool is_tree(AccelMethod m) { return m != AccelMethod::brute && m != AccelMethod::brute8; }

bool is_wide(AccelMethod m) { return tree_width(m) > 2; }

int tree_width(AccelMethod m) {
    switch (m) {
    case AccelMethod::bvh2: return 2;
    case AccelMethod::bvh4: return 4;
    case AccelMethod::bvh8: return 8;
    case AccelMethod::bvh16: return 16;
    default: return 0;
    }
}

double build_size_term(AccelMethod m, std::size_t triangles) {
    const double n = double(triangles);
    if (m == AccelMethod::brute) return 0.0;
    if (m == AccelMethod::brute8) return n;
    return n * std::log2(n + 1.0);
}

double ray_size_term(AccelMethod m, std::size_t triangles) {
    const double n = double(triangles);
    return is_tree(m) ? std::log2(n + 1.0) : n;
}

std::size_t brute_cache_triangles(AccelMethod m) {
    if (is_tree(m)) return 0;
    const Topology& t = topology();
    const std::size_t llc = t.l3_bytes ? t.l3_bytes : (t.l2_bytes ? t.l2_bytes : std::size_t(8) << 20);
    // brute8 streams Tri8 blocks (40 bytes per triangle); the scalar brute force reads the mesh: an index
    // triple and, on a closed mesh, half a vertex per triangle (a soup's 3 vertices are counted as 1).
    const std::size_t per_tri = m == AccelMethod::brute8 ? sizeof(Tri8) / 8 : sizeof(Triangle) + sizeof(Vec3);
    return llc / per_tri;
}

double ray_cache_term(AccelMethod m, std::size_t triangles) {
    if (is_tree(m)) return 0.0;
    // A cyclic stream larger than an LRU cache misses on every line: a step, not the excess.
    return triangles > brute_cache_triangles(m) ? double(triangles) : 0.0;
}

double predict_ms(const CostModel& model, AccelMethod m, std::size_t triangles, std::size_t rays, int threads) {
    const MethodCost& c = model.cost[std::size_t(m)];
    const double build = c.build0 + c.build1 * build_size_term(m, triangles);
    const double t = double(threads < 1 ? 1 : threads);
    const double per_ray = (c.ray0 + c.ray1 * ray_size_term(m, triangles)) / t + c.ray2 * ray_cache_term(m, triangles);
    const double par = std::clamp(c.build_par, 0.0, 1.0);
    // The trees' builds run on one thread below kMinPrimsForBuildThreads (build_threads.h).
    const double tb = is_tree(m) ? double(build_threads(int(t), triangles)) : t;
    return build * (1.0 - par + par / tb) + c.call + double(rays) * per_ray;
}

AccelChoice choose(const CostModel& model, std::size_t triangles, std::size_t rays, int threads) {
    AccelChoice c;
    c.isa = model.isa;
    c.triangles = triangles;
    c.rays = rays;
    c.threads = threads;
    for (AccelMethod m : kAccelMethods) c.predicted_ms[std::size_t(m)] = predict_ms(model, m, triangles, rays, threads);
    for (AccelMethod m : kAccelMethods)
        if (c.predicted_ms[std::size_t(m)] < c.predicted_ms[std::size_t(c.method)]) c.method = m;
    // choose() starts from bvh8: prefer the earliest method among exact ties.
    for (AccelMethod m : kAccelMethods)
        if (c.predicted_ms[std::size_t(m)] == c.predicted_ms[std::size_t(c.method)]) {
            c.method = m;
            break;
        }
    // Among the wide trees, BVH8 unless another width is predicted faster by
    // more than kWidthBuildError of BVH8's build. The widths share their BVH2
    // topology; their build terms, fitted apart on one machine, put BVH4's
    // build 3.4% below BVH8's and BVH16's 0.5% above (the AVX-512 set), where
    // an Intel Xeon (AVX-512) measured +2.3% and +8.2% (the dragon, one thread,
    // 9 paired rounds): so for 65,536 rays on the dragon the model chose BVH4,
    // which traced every ray set slowest there (1.16-1.34x BVH8's time) and
    // built slower, 377 ms in all against BVH8's 345 (camera rays). Past that
    // error the trace terms decide (BVH16 for ten million rays).
    if (c.method == AccelMethod::bvh4 || c.method == AccelMethod::bvh16) {
        // BVH8's build as predicted for these threads: its time without rays or the call.
        const double build8 = predict_ms(model, AccelMethod::bvh8, triangles, 0, threads) -
                              model.cost[std::size_t(AccelMethod::bvh8)].call;
        if (c.predicted_ms[std::size_t(AccelMethod::bvh8)] - c.predicted_ms[std::size_t(c.method)] <=
            kWidthBuildError * build8)
            c.method = AccelMethod::bvh8;
    }
    return c;
}

std::string describe(const AccelChoice& c) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s: predicted %.3g ms for %zu rays on %zu triangles (%d thread%s, %s model);",
                  std::string(name(c.method)).c_str(), c.predicted_ms[std::size_t(c.method)], c.rays, c.triangles,
                  c.threads, c.threads == 1 ? "" : "s", std::string(name(c.isa)).c_str());
    std::string s = buf;
    for (AccelMethod m : kAccelMethods) {
        std::snprintf(buf, sizeof buf, " %s %.3g ms", std::string(name(m)).c_str(), c.predicted_ms[std::size_t(m)]);
        s += buf;
    }
    return s;
}

}  // namespace simdbvh
