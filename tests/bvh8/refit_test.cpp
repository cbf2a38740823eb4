// BvhN<N>::refit (N = 4, 8, 16): a refit with the build's own mesh reproduces
// the nodes and blocks byte for byte (and the SAH cost); after a twist each
// child box bounds the vertices of its subtree's triangles (read from the
// mesh by id) and closest and any hits at every ISA are bit-identical to brute
// force on the moved mesh; 1 and 2 threads give the same bytes; bad meshes
// throw and leave the tree as it was.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/workloads/deform.h"
#include "simdbvh/workloads/rays.h"
#include "simdbvh/workloads/scenes.h"

namespace simdbvh {
namespace {

template <int N>
bool same_tree(const BvhN<N>& a, const BvhN<N>& b) {
    return a.nodes().size() == b.nodes().size() && a.blocks().size() == b.blocks().size() &&
           std::memcmp(a.nodes().data(), b.nodes().data(), a.nodes().size() * sizeof(NodeN<N>)) == 0 &&
           std::memcmp(a.blocks().data(), b.blocks().data(), a.blocks().size() * sizeof(Tri8)) == 0;
}

// The triangles under slot c of node i are within its box, for every slot of every node.
template <int N>
void expect_bounds(const BvhN<N>& bvh, const Mesh& mesh, std::uint32_t i, const Aabb& box) {
    const NodeN<N>& n = bvh.nodes()[i];
    for (int c = 0; c < N; ++c) {
        const ChildN<N>& ch = n.children[c];
        if (ch.is_empty()) continue;
        const Aabb cb = n.boxes.get(c);
        ASSERT_TRUE(box.contains(cb)) << "node " << i << " slot " << c;
        if (ch.is_inner()) {
            expect_bounds(bvh, mesh, ch.index, cb);
            continue;
        }
        for (std::uint32_t b = 0; b < ch.blocks(); ++b) {
            const Tri8& t = bvh.blocks()[ch.index + b];
            for (int k = 0; k < kBlockWidth; ++k) {
                const bool own = ch.own_lanes() ? (ch.own_lanes() >> k) & 1u : t.prim[k] != kInvalidPrim;
                if (!own) continue;
                for (int v = 0; v < 3; ++v) {
                    const Vec3 p = mesh.vertex(t.prim[k], v);
                    ASSERT_TRUE(cb.contains(Aabb{p, p})) << "node " << i << " slot " << c << " prim " << t.prim[k];
                }
            }
        }
    }
}

template <int N>
void check_width() {
    const Mesh mesh = workloads::random_soup(6000, 11);
    const BvhN<N> built = BvhN<N>::build(mesh);
    BvhN<N> b = built, b2 = built;
    b.refit(mesh);
    EXPECT_TRUE(same_tree(b, built)) << N;
    EXPECT_EQ(b.stats().sah_cost, built.stats().sah_cost) << N;
    const Aabb all{{-INFINITY, -INFINITY, -INFINITY}, {INFINITY, INFINITY, INFINITY}};
    for (double angle : {0.5, 2.5}) {
        const Mesh moved = workloads::twist(mesh, angle);
        b.refit(moved, 1);
        b2.refit(moved, 2);
        ASSERT_TRUE(same_tree(b, b2)) << N << " " << angle;
        expect_bounds(b, moved, 0, all);
        const Aabb mb = moved.bounds(), tb = b.bounds();
        EXPECT_TRUE(std::memcmp(&mb, &tb, sizeof(Aabb)) == 0) << N;
        auto rays = workloads::generate_rays(moved, workloads::RayKind::incoherent, 2000, 7);
        const auto prim = workloads::generate_rays(moved, workloads::RayKind::primary, 1000, 8);
        rays.insert(rays.end(), prim.begin(), prim.end());
        std::vector<Hit> want(rays.size());
        std::size_t hits = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) hits += (want[i] = brute_force_intersect(moved, rays[i])).hit();
        EXPECT_GT(hits, rays.size() / 4);
        for (Isa isa : supported_isas()) {
            std::vector<Hit> got(rays.size()), any(rays.size());
            intersect(b, rays, got, with_isa({}, isa));
            occluded(b, rays, any, with_isa({}, isa));
            for (std::size_t i = 0; i < rays.size(); ++i) {
                ASSERT_TRUE(got[i] == want[i]) << N << " " << name(isa) << " ray " << i;
                ASSERT_EQ(any[i].hit(), want[i].hit()) << N << " " << name(isa) << " ray " << i;
            }
        }
    }
    b.refit(mesh, 2);
    EXPECT_TRUE(same_tree(b, built)) << "twisted and back: the build again, N = " << N;

    Mesh fewer = mesh;
    fewer.triangles.pop_back();
    EXPECT_THROW(b.refit(fewer), Error);
    Mesh nan = workloads::twist(mesh, 1.0);
    nan.positions[nan.triangles.front()[0]].x = std::numeric_limits<float>::infinity();
    EXPECT_THROW(b.refit(nan), Error);
    EXPECT_TRUE(same_tree(b, built)) << N;
}

TEST(WideRefit, Bvh4) { check_width<4>(); }
TEST(WideRefit, Bvh8) { check_width<8>(); }
TEST(WideRefit, Bvh16) { check_width<16>(); }

TEST(WideRefit, EmptyMesh) {
    Bvh8 b = Bvh8::build(Mesh{});
    b.refit(Mesh{});
    EXPECT_TRUE(b.nodes().empty());
    EXPECT_THROW(b.refit(workloads::icosphere(0)), Error);
}

}  // namespace
}  // namespace simdbvh
