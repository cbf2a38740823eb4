// Seed 002's bounding-sphere hierarchy: the variance topology, one sphere per
// node, traversed by the binary loop (traverse_binary-inl.h) with a
// conservative ray/sphere node test.

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <type_traits>

#include "simdbvh/kernels/error.h"
#include "simdbvh/platform/parallel.h"
#include "simdbvh/bvh2/spheres.h"
#include "simdbvh/bvh2/internal/traverse_binary-inl.h"
#include "tree_shape.h"

namespace simdbvh {

namespace {

// The float at or above x (x >= 0, finite).
float round_up(double x) {
    float f = static_cast<float>(x);
    if (double(f) < x) f = std::nextafter(f, std::numeric_limits<float>::infinity());
    return f;
}
// The float at or below x.
float round_down(double x) {
    float f = static_cast<float>(x);
    if (double(f) > x) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
    return f;
}

}  // namespace

SphereBvh SphereBvh::build(const Mesh& mesh, const BuildOptions& in) {
    const auto t0 = std::chrono::steady_clock::now();
    validate(mesh);
    BuildOptions opts = in;
    opts.builder = Builder::variance;
    const std::size_t n = mesh.triangles.size();
    Bvh2Topology topo = build_topology(mesh, opts);
    SphereBvh bvh;
    bvh.tris_.resize(topo.prim_ids.size());
    for (std::size_t i = 0; i < topo.prim_ids.size(); ++i) {
        const std::uint32_t p = topo.prim_ids[i];
        bvh.tris_[i] = {mesh.vertex(p, 0), mesh.vertex(p, 1), mesh.vertex(p, 2)};
    }

    // Every subtree covers a contiguous range of the leaf order; children
    // always come after their parent, so one reverse pass gives the ranges and
    // the vertex sums (in double) bottom-up.
    const std::size_t nn = topo.nodes.size();
    std::vector<std::uint32_t> lo(nn), hi(nn);
    std::vector<std::array<double, 3>> sum(nn);
    for (std::size_t j = nn; j-- > 0;) {
        const Node2& nd = topo.nodes[j];
        if (nd.is_leaf()) {
            lo[j] = nd.first;
            hi[j] = nd.first + nd.count;
            std::array<double, 3> s{0, 0, 0};
            for (std::uint32_t i = lo[j]; i < hi[j]; ++i)
                for (const Vec3& v : {bvh.tris_[i].v0, bvh.tris_[i].v1, bvh.tris_[i].v2})
                    for (int a = 0; a < 3; ++a) s[a] += double(v[a]);
            sum[j] = s;
        } else {
            const std::uint32_t a = nd.first, b = nd.first + 1;
            if (a <= j || b >= nn) throw Error("spheres: unexpected node order");
            lo[j] = std::min(lo[a], lo[b]);
            hi[j] = std::max(hi[a], hi[b]);
            for (int k = 0; k < 3; ++k) sum[j][k] = sum[a][k] + sum[b][k];
        }
    }
    // Centre: the mean of the group's vertices; radius: the largest distance
    // to them, in double, rounded up to the next float.
    bvh.nodes_.resize(nn);
    ParallelOptions po;
    po.grain = 64;
    parallel_for(
        nn, std::max(1, opts.threads),
        [&](std::size_t b, std::size_t e) {
            for (std::size_t j = b; j < e; ++j) {
                const double cnt = 3.0 * double(hi[j] - lo[j]);
                const Vec3 c{float(sum[j][0] / cnt), float(sum[j][1] / cnt), float(sum[j][2] / cnt)};
                double r2 = 0;
                for (std::uint32_t i = lo[j]; i < hi[j]; ++i)
                    for (const Vec3& v : {bvh.tris_[i].v0, bvh.tris_[i].v1, bvh.tris_[i].v2}) {
                        const double dx = double(v.x) - double(c.x), dy = double(v.y) - double(c.y),
                                     dz = double(v.z) - double(c.z);
                        r2 = std::max(r2, dx * dx + dy * dy + dz * dz);
                    }
                const Node2& nd = topo.nodes[j];
                bvh.nodes_[j] = SphereNode{c, round_up(std::sqrt(r2)), nd.first, nd.count};
            }
        },
        po);

    const auto t1 = std::chrono::steady_clock::now();
    SphereBuildStats& s = bvh.stats_;
    s.build_ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
    s.nodes = nn;
    s.triangles = n;
    s.sah_cost = sah_cost(topo, opts.traversal_cost, opts.intersection_cost);
    if (nn) {
        const double r0 = double(bvh.nodes_[0].radius);
        double cost = 0;
        for (const SphereNode& nd : bvh.nodes_) {
            const double ratio = r0 > 0 ? double(nd.radius) * double(nd.radius) / (r0 * r0) : 1.0;
            cost += (nd.is_leaf() ? opts.intersection_cost * double(nd.count) : opts.traversal_cost) * ratio;
        }
        s.sphere_sah_cost = cost;
        const detail::TreeShape shape = detail::tree_shape(bvh.nodes_);
        s.depth = shape.depth;
        s.leaves = shape.leaves;
    }
    s.bytes_per_triangle =
        n ? double(nn * sizeof(SphereNode) + topo.prim_ids.size() * (sizeof(std::uint32_t) + sizeof(TriangleVerts))) /
                double(n)
          : 0.0;
    bvh.prim_ids_ = std::move(topo.prim_ids);
    return bvh;
}

// In double, the closest-approach form (Haines et al., "Precision Improvements
// for Ray/Sphere Intersection", Ray Tracing Gems ch. 7): the squared distance
// from the centre to the line is |f - (f.d / d.d) d|^2, with no catastrophic
// cancellation of b^2 - c. Everything from the float inputs is exact in double
// up to a few double roundings (~1e-16 relative). The triangle test decides in
// float on coordinates translated to the ray origin and sheared, so a hit is
// exact only for a ray and triangle perturbed by a few float ulps of the
// coordinates involved; the sphere is widened far beyond that (1e-5 relative
// to the magnitudes, ~170 float ulps), laterally and along the ray.
bool intersect_sphere(const PreparedRay& r, const SphereNode& s, float tmax, float* entry) {
    const double fx = double(s.center.x) - double(r.org.x);
    const double fy = double(s.center.y) - double(r.org.y);
    const double fz = double(s.center.z) - double(r.org.z);
    const double dx = r.dir.x, dy = r.dir.y, dz = r.dir.z;
    const double dd = dx * dx + dy * dy + dz * dz;  // > 0 for a valid ray (no underflow in double)
    const double tc = (fx * dx + fy * dy + fz * dz) / dd;
    const double qx = fx - tc * dx, qy = fy - tc * dy, qz = fz - tc * dz;
    const double q2 = qx * qx + qy * qy + qz * qz;
    // Magnitude scale of the coordinates the triangle test rounds.
    const double scale = std::fabs(fx) + std::fabs(fy) + std::fabs(fz) + std::fabs(double(r.org.x)) +
                         std::fabs(double(r.org.y)) + std::fabs(double(r.org.z)) + double(s.radius);
    const double rr = double(s.radius) + 1e-5 * scale;
    if (q2 > rr * rr) return false;  // NaN compares false: accepted
    const double h = std::sqrt(std::max(0.0, rr * rr - q2) / dd);
    const double tol = 1e-5 * (std::fabs(tc) + h + scale / std::sqrt(dd));
    const double near = tc - h - tol, far = tc + h + tol;
    if (far < double(r.tmin) || near > double(tmax)) return false;
    *entry = round_down(near);
    return true;
}

namespace {

// The width-2 node test of the sphere hierarchy: the two adjacent child spheres.
struct Sphere2Test {
    static bool root(const PreparedRay& r, const SphereNode& n, float tmax, float* entry) {
        return intersect_sphere(r, n, tmax, entry);
    }
    static std::uint32_t children(const PreparedRay& r, const SphereNode* nodes, const SphereNode& n, float tmax,
                                  float* e) {
        const bool ha = intersect_sphere(r, nodes[n.first], tmax, &e[0]);
        const bool hb = intersect_sphere(r, nodes[n.first + 1], tmax, &e[1]);
        return std::uint32_t(ha) | (std::uint32_t(hb) << 1);
    }
    static float cull(float t) { return cull_bound(t); }
};

template <TriangleTest kTest, bool kAnyHit, bool kStats>
Hit traverse(const SphereBvh& bvh, const Ray& ray, TraceStats* stats) {
    using Query = std::conditional_t<kAnyHit, query::AnyHit, query::ClosestHit>;
    const bvh2::TriangleLeaf<kTest, kStats> leaf{bvh.triangles().data(), bvh.prim_ids().data()};
    return bvh2::traverse_binary<Sphere2Test, Query, kStats>(bvh.nodes(), leaf, ray, stats);
}

template <bool kAnyHit>
Hit dispatch(const SphereBvh& bvh, const Ray& ray, const TraceOptions& o) {
    if (o.stats)
        return o.test == TriangleTest::watertight ? traverse<TriangleTest::watertight, kAnyHit, true>(bvh, ray, o.stats)
                                                  : traverse<TriangleTest::moller, kAnyHit, true>(bvh, ray, o.stats);
    return o.test == TriangleTest::watertight ? traverse<TriangleTest::watertight, kAnyHit, false>(bvh, ray, nullptr)
                                              : traverse<TriangleTest::moller, kAnyHit, false>(bvh, ray, nullptr);
}

template <bool kAnyHit>
void dispatch_span(const SphereBvh& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& o) {
    simdbvh::detail::check_size(hits.size(), rays.size(), "hits");
    if (o.stats) {
        for (std::size_t i = 0; i < rays.size(); ++i) hits[i] = dispatch<kAnyHit>(bvh, rays[i], o);
        return;
    }
    parallel_for(rays.size(), o.threads, [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) hits[i] = dispatch<kAnyHit>(bvh, rays[i], o);
    });
}

}  // namespace

Hit intersect(const SphereBvh& bvh, const Ray& ray, const TraceOptions& o) { return dispatch<false>(bvh, ray, o); }
Hit occluded(const SphereBvh& bvh, const Ray& ray, const TraceOptions& o) { return dispatch<true>(bvh, ray, o); }
void intersect(const SphereBvh& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& o) {
    dispatch_span<false>(bvh, rays, hits, o);
}
void occluded(const SphereBvh& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& o) {
    dispatch_span<true>(bvh, rays, hits, o);
}

}  // namespace simdbvh
