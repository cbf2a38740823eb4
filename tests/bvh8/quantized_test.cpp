// Quantized nodes (qnode.h, WideOptions::quantized_nodes), N = 8, 16 (a BVH4 with them is an Error):
// every dequantized child box contains the full node's box for that slot and
// lies within two grid steps of it, the children and used slots are copied;
// traversal at every ISA gives hits bit-identical to the full nodes and to
// brute force, and every ISA visits the same quantized nodes; a refit
// requantizes; an extent no 8-bit grid spans falls back to the full nodes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>

#include "simdbvh/bvh8/internal/quantize.h"
#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/workloads/deform.h"
#include "simdbvh/workloads/rays.h"
#include "simdbvh/workloads/scenes.h"

namespace simdbvh {
namespace {

using workloads::RayKind;

WideOptions quantized() {
    WideOptions o;
    o.quantized_nodes = true;
    return o;
}

// The grid step of axis a of a quantized box.
template <int N>
float step(const QBoxN<N>& q, int a) {
    return std::ldexp(1.0f, int(q.exp[a]) - 127);
}

template <int N>
void expect_quantized(const BvhN<N>& bvh, const std::string& what) {
    ASSERT_EQ(bvh.qnodes().size(), bvh.nodes().size()) << what;
    for (std::size_t i = 0; i < bvh.nodes().size(); ++i) {
        const NodeN<N>& n = bvh.nodes()[i];
        const QNodeN<N>& q = bvh.qnodes()[i];
        ASSERT_EQ(std::memcmp(n.children, q.children, sizeof(n.children)), 0) << what << " node " << i;
        for (int c = 0; c < N; ++c) {
            ASSERT_EQ((q.boxes.valid >> c) & 1u, n.children[c].is_empty() ? 0u : 1u) << what << " node " << i;
            if (n.children[c].is_empty()) continue;
            const Aabb full = n.boxes.get(c), got = q.boxes.get(c);
            ASSERT_TRUE(got.contains(full)) << what << " node " << i << " slot " << c;
            for (int a = 0; a < 3; ++a) {
                const float s = step(q.boxes, a);
                EXPECT_LE(full.lo[a] - got.lo[a], 2 * s) << what << " node " << i << " slot " << c << " axis " << a;
                EXPECT_LE(got.hi[a] - full.hi[a], 2 * s) << what << " node " << i << " slot " << c << " axis " << a;
                // The step is the smallest power of two spanning the node's extent in 255 steps, up to one doubling.
                const float extent = got.hi[a] - q.boxes.origin[a];
                EXPECT_LE(extent, 256 * s) << what << " node " << i;
            }
        }
    }
}

template <int N>
void expect_same_hits(const Mesh& mesh, const std::vector<Ray>& rays, const std::string& what) {
    const Bvh2 bvh2 = Bvh2::build(mesh);
    const BvhN<N> full = BvhN<N>::build(bvh2), q = BvhN<N>::build(bvh2, quantized());
    expect_quantized(q, what);
    EXPECT_GT(q.stats().bytes_per_triangle, full.stats().bytes_per_triangle);  // both node arrays are kept
    std::vector<Hit> want(rays.size()), want_any(rays.size()), got(rays.size()), any(rays.size());
    intersect(full, rays, want, with_isa({}, Isa::scalar));
    occluded(full, rays, want_any, with_isa({}, Isa::scalar));
    TraceStats ref;
    for (Isa isa : kAllIsas) {
        if (!supported(isa)) continue;
        TraceStats st;
        TraceOptions o;
        o.stats = &st;
        intersect(q, rays, got, with_isa(o, isa));
        occluded(q, rays, any, with_isa({}, isa));
        for (std::size_t i = 0; i < rays.size(); ++i) {
            ASSERT_EQ(got[i], want[i]) << what << " bvh" << N << " " << name(isa) << " ray " << i;
            ASSERT_EQ(any[i].hit(), want_any[i].hit()) << what << " bvh" << N << " " << name(isa) << " ray " << i;
            if (i % 13 == 0) {
                ASSERT_EQ(got[i], brute_force_intersect(mesh, rays[i])) << what << " ray " << i;
            }
        }
        if (isa == Isa::scalar) ref = st;
        EXPECT_EQ(st.nodes_visited, ref.nodes_visited) << what << " bvh" << N << " " << name(isa);
        EXPECT_EQ(st.triangle_tests, ref.triangle_tests) << what << " bvh" << N << " " << name(isa);
    }
}

template <int N>
void check_meshes() {
    for (const std::string s : {"icosphere-4", "soup-3000", "dragon-res4"}) {
        if (s == "dragon-res4" && !workloads::is_cached(s)) continue;
        const Mesh mesh = workloads::load_scene(s);
        for (RayKind k : {RayKind::primary, RayKind::incoherent}) {
            std::vector<Ray> rays = workloads::generate_rays(mesh, k, 3000, 41);
            const Aabb b = mesh.bounds();
            // Axis-aligned rays with +-0 components from the bounds' corners (the box planes).
            for (float sx : {0.0f, -0.0f, 1.0f, -1.0f})
                for (float sy : {0.0f, -0.0f, 1.0f, -1.0f})
                    for (const Vec3& o : {b.lo, b.hi, Vec3{b.lo.x, b.hi.y, 0}}) rays.push_back({o, 0, {sx, sy, 1.0f}});
            expect_same_hits<N>(mesh, rays, s + " " + std::string(workloads::name(k)));
        }
    }
}

TEST(QuantizedNodes, Bvh4IsAnError) {
    const Mesh m = workloads::random_soup(100, 3);
    EXPECT_THROW(Bvh4::build(m, {}, quantized()), Error);
    const Bvh2 b2 = Bvh2::build(m);
    EXPECT_THROW(Bvh4::build(b2, quantized()), Error);
    EXPECT_NO_THROW(Bvh4::build(m, {}, WideOptions{}));
}
TEST(QuantizedNodes, Bvh8SameHitsEveryIsa) { check_meshes<8>(); }
TEST(QuantizedNodes, Bvh16SameHitsEveryIsa) { check_meshes<16>(); }

// Far from the origin (the grid's origin and step are large) and tiny (steps
// near the smallest normal float): the boxes still contain their children.
TEST(QuantizedNodes, FarAndTinyCoordinates) {
    for (const double scale : {1e30, 1e-30, 1.0}) {
        for (const double offset : {0.0, 1e6, -3e7}) {
            Mesh m = workloads::random_soup(2000, 7);
            for (Vec3& v : m.positions) {
                v.x = float(v.x * scale + offset);
                v.y = float(v.y * scale - offset);
                v.z = float(v.z * scale);
            }
            const std::string what = "scale " + std::to_string(scale) + " offset " + std::to_string(offset);
            const Bvh8 q = Bvh8::build(m, {}, quantized());
            expect_quantized(q, what);
            const auto rays = workloads::generate_rays(m, RayKind::incoherent, 800, 3);
            std::vector<Hit> got(rays.size());
            intersect(q, rays, got);
            for (std::size_t i = 0; i < rays.size(); i += 5)
                ASSERT_EQ(got[i], brute_force_intersect(m, rays[i])) << what << " ray " << i;
        }
    }
}

// An axis wider than 255 * 2^119: no 8-bit grid of finite steps spans it, so
// the box is refused and the tree keeps only its full nodes.
TEST(QuantizedNodes, TooWideFallsBackToFullNodes) {
    Box8 box;
    box.clear();
    ChildN<8> children[8];
    for (auto& c : children) c = ChildN<8>::empty();
    box.set(0, Aabb{{-3e38f, 0, 0}, {-2e38f, 1, 1}});
    box.set(1, Aabb{{2e38f, 0, 0}, {3e38f, 1, 1}});
    children[0] = children[1] = ChildN<8>::leaf(0, 1);
    QBoxN<8> q;
    EXPECT_FALSE(bvh8::quantize_box<8>(box, children, q));
    box.set(0, Aabb{{-0.8e38f, 0, 0}, {-0.5e38f, 1, 1}});  // 1.6e38 wide: 255 * 2^119 (1.69e38) spans it
    box.set(1, Aabb{{-0.5e38f, 0, 0}, {0.8e38f, 1, 1}});
    EXPECT_TRUE(bvh8::quantize_box<8>(box, children, q));
    EXPECT_TRUE(q.get(0).contains(box.get(0)));
    EXPECT_TRUE(q.get(1).contains(box.get(1)));

    Mesh m;
    m.positions = {{-3e38f, 0, 0}, {-3e38f, 1, 0}, {-3e38f, 0, 1}, {3e38f, 0, 0}, {3e38f, 1, 0}, {3e38f, 0, 1}};
    m.triangles = {{0, 1, 2}, {3, 4, 5}};
    const Bvh8 b = Bvh8::build(m, {}, quantized());
    EXPECT_TRUE(b.qnodes().empty());
    const Ray r{{-3.3e38f, 0.25f, 0.25f}, 0, {1, 0, 0}};
    std::vector<Hit> got(1);
    intersect(b, std::span<const Ray>(&r, 1), got);
    EXPECT_EQ(got[0], brute_force_intersect(m, r));
    EXPECT_EQ(got[0].prim, 0u);
}

// A refit requantizes in place: the quantized boxes contain the moved
// children and the hits are brute force's on the moved mesh.
TEST(QuantizedNodes, RefitRequantizes) {
    const Mesh mesh = workloads::random_soup(5000, 13);
    Bvh8 b = Bvh8::build(mesh, {}, quantized());
    const Mesh moved = workloads::twist(mesh, 1.2);
    b.refit(moved, 2);
    expect_quantized(b, "twisted");
    const auto rays = workloads::generate_rays(moved, RayKind::incoherent, 2000, 9);
    std::vector<Hit> got(rays.size());
    for (Isa isa : kAllIsas) {
        if (!supported(isa)) continue;
        intersect(b, rays, got, with_isa({}, isa));
        for (std::size_t i = 0; i < rays.size(); i += 3)
            ASSERT_EQ(got[i], brute_force_intersect(moved, rays[i])) << name(isa) << " ray " << i;
    }
}

}  // namespace
}  // namespace simdbvh
