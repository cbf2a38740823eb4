// Every 8-wide kernel in every ISA the CPU has equals the scalar reference bit
// for bit: masks, entry distances, and Hit (t, u, v, prim), on randomized and
// edge-case inputs. Unsupported ISAs are skipped, not passed.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "kernel_test_util.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/kernels/box.h"
#include "simdbvh/kernels/triangle.h"

namespace simdbvh {
namespace {

using kernels::Tri1;
using test::bits_of;
using test::hit_str;
using test::Rng;

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr TriangleTest kTests[] = {TriangleTest::watertight, TriangleTest::moller};

const char* test_name(TriangleTest t) { return t == TriangleTest::watertight ? "watertight" : "moller"; }

bool hit_has_nan(const Hit& h) { return std::isnan(h.t) || std::isnan(h.u) || std::isnan(h.v); }

class KernelsVsScalar : public testing::TestWithParam<Isa> {
protected:
    void SetUp() override { SIMDBVH_SKIP_IF_UNSUPPORTED(GetParam()); }

    // Box8: masks and all 8 entries per ray, bit for bit; count_box8_hits agrees.
    void check_box8(const std::vector<Ray>& rays, const Box8& box, const char* what) {
        const Isa isa = GetParam();
        std::vector<std::uint8_t> m0(rays.size()), m1(rays.size());
        std::vector<float> e0(8 * rays.size()), e1(8 * rays.size());
        kernels::intersect_box8(rays, box, m0, e0, Isa::scalar);
        kernels::intersect_box8(rays, box, m1, e1, isa);
        ASSERT_EQ(kernels::last_isa_used(), isa);
        std::uint64_t hits = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            ASSERT_EQ(m0[i], m1[i]) << what << ": ray " << i;
            hits += std::uint64_t(__builtin_popcount(m0[i]));
            for (int j = 0; j < 8; ++j) {
                ASSERT_EQ(bits_of(e0[8 * i + j]), bits_of(e1[8 * i + j]))
                    << what << ": ray " << i << " box " << j << " entry " << e0[8 * i + j] << " vs " << e1[8 * i + j];
                if ((m0[i] >> j) & 1) {
                    ASSERT_FALSE(std::isnan(e0[8 * i + j])) << what << ": NaN entry of a hit";
                }
            }
            // The scalar kernel is the reference function itself.
            const PreparedRay p = prepare(rays[i]);
            for (int j = 0; j < 8 && p.valid; ++j) {
                float e;
                ASSERT_EQ(intersect_box(p, box.get(j), p.tmax, &e), bool((m0[i] >> j) & 1));
            }
        }
        ASSERT_EQ(kernels::count_box8_hits(rays, {&box, 1}, isa), hits) << what;

        // The grouped form: the box, its lanes reversed, and the box again;
        // each group's masks and entries are the single-box kernel's (scalar).
        Box8 reversed;
        reversed.clear();
        for (int j = 0; j < 8; ++j) reversed.set(j, box.get(7 - j));
        const std::vector<Box8> groups = {box, reversed, box};
        const std::size_t ng = groups.size();
        std::vector<std::uint8_t> mg(ng * rays.size());
        std::vector<float> eg(8 * ng * rays.size());
        kernels::intersect_box8_groups(rays, groups, mg, eg, isa);
        ASSERT_EQ(kernels::last_isa_used(), isa);
        for (std::size_t g = 0; g < ng; ++g) {
            std::vector<std::uint8_t> mr(rays.size());
            std::vector<float> er(8 * rays.size());
            kernels::intersect_box8(rays, groups[g], mr, er, Isa::scalar);
            for (std::size_t i = 0; i < rays.size(); ++i) {
                ASSERT_EQ(mg[ng * i + g], mr[i]) << what << ": group " << g << " ray " << i;
                for (int j = 0; j < 8; ++j)
                    ASSERT_EQ(bits_of(eg[8 * (ng * i + g) + std::size_t(j)]), bits_of(er[8 * i + std::size_t(j)]))
                        << what << ": group " << g << " ray " << i << " box " << j;
            }
        }
        if (!rays.empty()) {
            EXPECT_THROW(kernels::intersect_box8_groups(rays, groups, std::span(mg).first(mg.size() - 1), eg, isa),
                         Error)
                << what;
        }
        check_nested(rays, box, what);
        check_tree(rays, box, what);
        check_boxes(rays, box, what);
    }

    // collect_boxes over the box's lanes, their middle halves and lane 3 again
    // (17 boxes: two full groups and one lane of a third), that pattern
    // repeated to 100 boxes (more than the 64 a mask word holds), and over
    // the first 8, 1 and 0: each ray reports exactly the boxes intersect_box
    // hits, in index order, with its entries in the caller's t, for scalar and
    // this ISA, with every ray live or only some (whole groups of 8 dead too);
    // more than kCollectBoxesMax boxes and wrong span sizes throw.
    void check_boxes(const std::vector<Ray>& rays, const Box8& box, const char* what) {
        const Isa isa = GetParam();
        std::vector<Aabb> boxes;
        for (int j = 0; j < 8; ++j) boxes.push_back(box.get(j));
        for (int j = 0; j < 8; ++j) boxes.push_back(middle_half(box.get(j)));
        boxes.push_back(box.get(3));
        while (boxes.size() < 100) boxes.push_back(boxes[boxes.size() % 17]);
        using Found = std::vector<std::pair<float, std::uint32_t>>;
        std::vector<Found> want(rays.size());
        for (std::size_t i = 0; i < rays.size(); ++i) {
            const PreparedRay p = prepare(rays[i]);
            for (std::size_t b = 0; b < boxes.size() && p.valid; ++b) {
                float e;
                if (intersect_box(p, boxes[b], p.tmax, &e)) want[i].push_back({to_caller_t(p, e), std::uint32_t(b)});
            }
        }
        std::vector<std::uint8_t> some(rays.size()), groups(rays.size());
        for (std::size_t i = 0; i < rays.size(); ++i) {
            some[i] = std::uint8_t(i % 3 != 1);
            groups[i] = std::uint8_t((i / 8) % 2);
        }
        const std::vector<std::uint8_t> none;
        const std::vector<const std::vector<std::uint8_t>*> lives = {&none, &some, &groups};
        const std::vector<std::size_t> counts = {boxes.size(), 17, 8, 1, 0};
        for (Isa run : {Isa::scalar, isa})
            for (const std::vector<std::uint8_t>* live : lives)
                for (const std::size_t count : counts) {
                    Found out{{-1.0f, 7u}};  // appended to: what was there stays
                    std::vector<std::uint32_t> first(rays.size() + 1);
                    kernels::collect_boxes(rays, *live, std::span(boxes).first(count), out, first, run);
                    ASSERT_EQ(kernels::last_isa_used(), run);
                    ASSERT_EQ(out.size(), first.back()) << what;
                    ASSERT_EQ(first[0], 1u) << what;
                    for (std::size_t i = 0; i < rays.size(); ++i) {
                        const Found got(out.begin() + first[i], out.begin() + first[i + 1]);
                        Found expect;
                        if (live->empty() || (*live)[i] != 0)
                            for (const auto& f : want[i])
                                if (f.second < count) expect.push_back(f);
                        ASSERT_EQ(got.size(), expect.size())
                            << what << ": " << name(run) << " ray " << i << ", " << count << " boxes";
                        for (std::size_t k = 0; k < got.size(); ++k) {
                            ASSERT_EQ(got[k].second, expect[k].second) << what << ": " << name(run) << " ray " << i;
                            ASSERT_EQ(bits_of(got[k].first), bits_of(expect[k].first))
                                << what << ": " << name(run) << " ray " << i << " box " << got[k].second << " entry "
                                << got[k].first << " vs " << expect[k].first;
                        }
                    }
                }
        Found out;
        std::vector<std::uint32_t> first(rays.size() + 1);
        const std::vector<Aabb> too_many(kernels::kCollectBoxesMax + 1, box.get(0));
        EXPECT_THROW(kernels::collect_boxes(rays, {}, too_many, out, first, isa), Error) << what;
        EXPECT_THROW(kernels::collect_boxes(rays, {}, boxes, out, std::span(first).first(rays.size()), isa), Error)
            << what;
        if (!rays.empty()) {
            EXPECT_THROW(kernels::collect_boxes(rays, std::span(some).first(rays.size() - 1), boxes, out, first, isa),
                         Error)
                << what;
        }
    }

    // The box tree: a root whose lanes hold node 1 (the box's 8 lanes, leaves
    // 0-7), node 2 (their middle halves, leaves 8-15), leaf 100 (lane 3's box)
    // and node 3 (lane 0's box over one leaf, 200: its middle half), each lane's
    // box holding the boxes below it. Each ray must reach exactly the leaves
    // whose own lane the scalar single-node kernel hits, with those entries,
    // for scalar and this ISA; rays not live reach none; malformed trees throw.
    void check_tree(const std::vector<Ray>& rays, const Box8& box, const char* what) {
        const Isa isa = GetParam();
        std::vector<Box8> nodes(4);
        for (Box8& b : nodes) b.clear();
        std::vector<std::uint32_t> children(32, kernels::kBoxTreeEmpty);
        Aabb all, halves;
        for (int j = 0; j < 8; ++j) {
            nodes[1].set(j, box.get(j));
            nodes[2].set(j, middle_half(box.get(j)));
            children[8 + std::size_t(j)] = kernels::kBoxTreeLeaf | std::uint32_t(j);
            children[16 + std::size_t(j)] = kernels::kBoxTreeLeaf | std::uint32_t(8 + j);
            all.grow(box.get(j));
            halves.grow(middle_half(box.get(j)));
        }
        nodes[0].set(0, all);
        nodes[0].set(1, halves);
        nodes[0].set(2, box.get(3));
        nodes[0].set(3, box.get(0));
        nodes[3].set(0, middle_half(box.get(0)));
        children[0] = 1;
        children[1] = 2;
        children[2] = kernels::kBoxTreeLeaf | 100u;
        children[3] = 3;
        children[24] = kernels::kBoxTreeLeaf | 200u;
        // The expected leaves: each leaf's own node tested alone (scalar).
        using Found = std::vector<std::pair<float, std::uint32_t>>;
        std::vector<Found> want(rays.size());
        for (std::size_t node = 0; node < nodes.size(); ++node) {
            std::vector<std::uint8_t> m(rays.size());
            std::vector<float> e(8 * rays.size());
            kernels::intersect_box8(rays, nodes[node], m, e, Isa::scalar);
            for (std::size_t i = 0; i < rays.size(); ++i)
                for (int j = 0; j < 8; ++j) {
                    const std::uint32_t c = children[8 * node + std::size_t(j)];
                    if (((m[i] >> j) & 1) && c != kernels::kBoxTreeEmpty && (c & kernels::kBoxTreeLeaf))
                        want[i].push_back({e[8 * i + std::size_t(j)], c & ~kernels::kBoxTreeLeaf});
                }
        }
        auto same = [](Found a, Found b) {
            std::sort(a.begin(), a.end());
            std::sort(b.begin(), b.end());
            if (a.size() != b.size()) return false;
            for (std::size_t k = 0; k < a.size(); ++k)
                if (bits_of(a[k].first) != bits_of(b[k].first) || a[k].second != b[k].second) return false;
            return true;
        };
        std::vector<std::uint8_t> live(rays.size());
        for (std::size_t i = 0; i < rays.size(); ++i) live[i] = std::uint8_t(i % 3 != 1);
        for (Isa run : {Isa::scalar, isa})
            for (const bool all_live : {true, false}) {
                Found out{{-1.0f, 7u}};  // appended to: what was there stays
                std::vector<std::uint32_t> first(rays.size() + 1);
                kernels::collect_box8_tree(rays, all_live ? std::span<const std::uint8_t>() : live, nodes, children,
                                           out, first, run);
                ASSERT_EQ(kernels::last_isa_used(), run);
                ASSERT_EQ(out.size(), first.back()) << what;
                ASSERT_EQ(first[0], 1u) << what;
                for (std::size_t i = 0; i < rays.size(); ++i) {
                    const Found got(out.begin() + first[i], out.begin() + first[i + 1]);
                    if (!all_live && !live[i]) {
                        ASSERT_TRUE(got.empty()) << what << ": ray " << i << " is not live";
                        continue;
                    }
                    ASSERT_TRUE(same(got, want[i])) << what << ": " << name(run) << " ray " << i << ": " << got.size()
                                                    << " leaves, want " << want[i].size();
                }
            }
        Found out;
        std::vector<std::uint32_t> first(rays.size() + 1);
        auto bad = children;
        bad[3] = 0;  // the root as its own child
        EXPECT_THROW(kernels::collect_box8_tree(rays, {}, nodes, bad, out, first, isa), Error) << what;
        bad = children;
        bad[4] = 3;  // node 3 reached from two lanes
        EXPECT_THROW(kernels::collect_box8_tree(rays, {}, nodes, bad, out, first, isa), Error) << what;
        bad = children;
        bad[9] = 4;  // past the last node
        EXPECT_THROW(kernels::collect_box8_tree(rays, {}, nodes, bad, out, first, isa), Error) << what;
        EXPECT_THROW(kernels::collect_box8_tree(rays, {}, nodes, std::span(children).first(31), out, first, isa),
                     Error);
        EXPECT_THROW(
            kernels::collect_box8_tree(rays, {}, nodes, children, out, std::span(first).first(rays.size()), isa),
            Error);
    }

    // The nested form: the groups above plus, per lane k, a group holding only
    // lane k's box shrunk to its middle half, under supers whose lanes are the
    // groups' unions (lanes 0-2) and the unshrunk boxes (the single-lane groups):
    // masks equal the flat grouped form's, scalar and this ISA, and entries
    // where a mask bit is set; untested groups have +inf entries.
    // b's middle half on each axis where that is a box (else b's extent there).
    static Aabb middle_half(const Aabb& b) {
        Aabb in = b;
        for (int a = 0; a < 3; ++a) {
            const float q = (b.hi[a] - b.lo[a]) * 0.25f;
            if (std::isfinite(q) && b.lo[a] + q <= b.hi[a] - q) {
                in.lo[a] = b.lo[a] + q;
                in.hi[a] = b.hi[a] - q;
            }
        }
        return in;
    }

    void check_nested(const std::vector<Ray>& rays, const Box8& box, const char* what) {
        const Isa isa = GetParam();
        Box8 reversed;
        reversed.clear();
        for (int j = 0; j < 8; ++j) reversed.set(j, box.get(7 - j));
        std::vector<Box8> groups = {box, reversed, box};
        std::vector<Box8> supers(2);
        for (Box8& s : supers) s.clear();
        for (int g = 0; g < 3; ++g) {
            Aabb u;
            for (int j = 0; j < 8; ++j) u.grow(groups[std::size_t(g)].get(j));
            supers[0].set(g, u);
        }
        for (int k = 0; k < 8; ++k) {
            const Aabb b = box.get(k);
            Box8 one;
            one.clear();
            one.set(k, middle_half(b));
            groups.push_back(one);
            supers[std::size_t(3 + k) / 8].set((3 + k) % 8, b);
        }
        const std::size_t ng = groups.size();
        std::vector<std::uint8_t> mf(ng * rays.size()), mn(ng * rays.size());
        std::vector<float> ef(8 * ng * rays.size()), en(8 * ng * rays.size());
        kernels::intersect_box8_groups(rays, groups, mf, ef, Isa::scalar);
        for (Isa run : {Isa::scalar, isa}) {
            kernels::intersect_box8_nested(rays, supers, groups, mn, en, run);
            ASSERT_EQ(kernels::last_isa_used(), run);
            for (std::size_t i = 0; i < rays.size(); ++i)
                for (std::size_t g = 0; g < ng; ++g) {
                    const std::size_t c = ng * i + g;
                    ASSERT_EQ(mn[c], mf[c]) << what << ": nested, group " << g << " ray " << i;
                    for (int j = 0; j < 8; ++j) {
                        const float e = en[8 * c + std::size_t(j)];
                        if ((mn[c] >> j) & 1) {
                            ASSERT_EQ(bits_of(e), bits_of(ef[8 * c + std::size_t(j)])) << what;
                        }
                    }
                }
        }
        // A ray that misses a super lane leaves its group untested: +inf entries.
        std::vector<Ray> away{Ray{{1e6f, 1e6f, 1e6f}, 0, {1, 0, 0}, kInf}};
        std::vector<std::uint8_t> m1(ng);
        std::vector<float> e1(8 * ng, 0.0f);
        kernels::intersect_box8_nested(away, supers, groups, m1, e1, isa);
        for (std::size_t g = 0; g < ng; ++g)
            if (m1[g] == 0) {
                for (int j = 0; j < 8; ++j) ASSERT_EQ(e1[8 * g + std::size_t(j)], kInf) << what << ": group " << g;
            }
        EXPECT_THROW(kernels::intersect_box8_nested(rays, std::span(supers).first(1), groups, mn, en, isa), Error);
    }

    // Tri8: closest hit over all blocks, each block alone, and any-hit, bit for bit.
    void check_tri8(const std::vector<Ray>& rays, const std::vector<Tri8>& blocks, const char* what,
                    std::vector<Hit>* closest_out = nullptr, TriangleTest only = TriangleTest::watertight,
                    bool only_one = false) {
        const Isa isa = GetParam();
        for (TriangleTest test : kTests) {
            if (only_one && test != only) continue;
            std::vector<Hit> h0(rays.size()), h1(rays.size());
            kernels::intersect_tri8(rays, blocks, test, h0, Isa::scalar);
            kernels::intersect_tri8(rays, blocks, test, h1, isa);
            ASSERT_EQ(kernels::last_isa_used(), isa);
            for (std::size_t i = 0; i < rays.size(); ++i) {
                ASSERT_EQ(h0[i], h1[i]) << what << " " << test_name(test) << ": ray " << i << " scalar "
                                        << hit_str(h0[i]) << " " << name(isa) << " " << hit_str(h1[i]);
                if (h0[i].hit()) {
                    ASSERT_FALSE(hit_has_nan(h0[i])) << what << ": NaN in a reported hit " << hit_str(h0[i]);
                    ASSERT_NE(h0[i].prim, kInvalidPrim);
                } else {
                    ASSERT_EQ(h0[i], Hit{}) << what << ": a miss is Hit{}";
                }
            }
            if (closest_out && test == (only_one ? only : TriangleTest::watertight)) *closest_out = h0;
            for (std::size_t b = 0; b < blocks.size(); ++b) {
                std::span<const Tri8> one(&blocks[b], 1);
                kernels::intersect_tri8(rays, one, test, h0, Isa::scalar);
                kernels::intersect_tri8(rays, one, test, h1, isa);
                for (std::size_t i = 0; i < rays.size(); ++i)
                    ASSERT_EQ(h0[i], h1[i]) << what << " " << test_name(test) << ": block " << b << " ray " << i
                                            << " scalar " << hit_str(h0[i]) << " vs " << hit_str(h1[i]);
            }
            std::vector<std::uint8_t> o0(rays.size()), o1(rays.size());
            kernels::occluded_tri8(rays, blocks, test, o0, h0, Isa::scalar);
            kernels::occluded_tri8(rays, blocks, test, o1, h1, isa);
            for (std::size_t i = 0; i < rays.size(); ++i) {
                ASSERT_EQ(o0[i], o1[i]) << what << " " << test_name(test) << " occluded: ray " << i;
                ASSERT_EQ(h0[i], h1[i]) << what << " " << test_name(test) << " first hit: ray " << i << " "
                                        << hit_str(h0[i]) << " vs " << hit_str(h1[i]);
                ASSERT_EQ(o0[i] != 0, h0[i].hit());
            }
        }
    }
};

// ---------- boxes ----------

Aabb random_box(Rng& rng) {
    const Vec3 c = rng.in_box(-1, 1);
    Vec3 e = rng.in_box(0, 0.5f);
    if (rng.chance(0.1f)) e.x = 0;  // flat boxes
    if (rng.chance(0.1f)) e.y = 0;
    return {c - e, c + e};
}

Ray random_ray(Rng& rng, float span) {
    Ray r;
    r.org = rng.in_box(-span, span);
    r.dir = rng.direction();
    if (rng.chance(0.1f)) r.dir.x = rng.chance(0.5f) ? 0.0f : -0.0f;
    if (rng.chance(0.1f)) r.dir.y = rng.chance(0.5f) ? 0.0f : -0.0f;
    if (rng.chance(0.05f)) r.dir.z = rng.chance(0.5f) ? 0.0f : -0.0f;
    r.tmin = rng.chance(0.7f) ? 0.0f : rng.range(0, 2);
    r.tmax = rng.chance(0.5f) ? kInf : rng.range(0, 6);
    return r;
}

// ---------- ray set-up ----------

// prepare_rays on every ISA is prepare() and intersect_box per ray, every
// field bit for bit: ties between the largest direction components (the
// watertight permutation's first of equals), signed zeros, subnormal, tiny and
// huge (rescaled) directions, negative tmin, invalid rays, origins on the
// bounds' planes, batches that are no multiple of 8, and no bounds at all.
TEST_P(KernelsVsScalar, PrepareRaysIsPrepareAndTheBoundsTest) {
    const Isa isa = GetParam();
    Rng rng(29);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const Aabb bounds{{-1.0f, -0.5f, -2.0f}, {1.5f, 0.75f, 0.25f}};
    int ok_count = 0, missed = 0, ties = 0, rescaled = 0, flushed = 0, negative_tmin = 0, invalid = 0;
    for (const std::size_t n : {std::size_t(1), std::size_t(7), std::size_t(8), std::size_t(203), std::size_t(3000)}) {
        std::vector<Ray> rays;
        for (std::size_t i = 0; i < n; ++i) {
            Ray r = random_ray(rng, 1.5f);
            switch (rng.below(10)) {
            case 0: {  // ties among the largest components, any signs
                const float a = rng.range(0.1f, 2.0f);
                r.dir = {rng.chance(0.5f) ? a : -a, rng.chance(0.5f) ? a : -a, rng.chance(0.5f) ? a : -a};
                if (rng.chance(0.5f)) r.dir[rng.below(3)] = rng.chance(0.5f) ? 0.0f : -0.0f;
                break;
            }
            case 1: {  // tiny, huge and subnormal directions
                const float scales[] = {0x1p-40f, 0x1p-135f, 0x1p40f, 0x1p-20f};
                const float sc = scales[rng.below(4)];
                r.dir = {r.dir.x * sc, r.dir.y * sc, r.dir.z * sc};
                if (rng.chance(0.7f)) r.dir[rng.below(3)] = rng.chance(0.5f) ? 0x1.8p-127f : -1e-40f;
                if (r.dir.x == 0 && r.dir.y == 0 && r.dir.z == 0) r.dir.z = sc;
                break;
            }
            case 2:  // an origin on a plane of the bounds
                r.org[rng.below(3)] = rng.chance(0.5f) ? bounds.lo[rng.below(3)] : bounds.hi[rng.below(3)];
                break;
            case 3: r.tmin = -rng.range(0.0f, 4.0f); break;
            case 4: {  // invalid
                const int k = rng.below(6);
                if (k == 0) r.org.y = nan;
                if (k == 1) r.dir.x = kInf;
                if (k == 2) r.dir = {0.0f, -0.0f, 0.0f};
                if (k == 3) r.tmin = nan;
                if (k == 4) r.tmax = -1.0f;
                if (k == 5) r.org.z = -kInf;
                break;
            }
            default: break;
            }
            rays.push_back(r);
        }
        for (const Aabb* b : {&bounds, static_cast<const Aabb*>(nullptr)}) {
            std::vector<PreparedRay> out(n);
            std::vector<std::uint8_t> ok(n, 7);
            kernels::prepare_rays(rays, b, out, ok, isa);
            for (std::size_t i = 0; i < n; ++i) {
                const PreparedRay p = prepare(rays[i]);
                float entry;
                const bool want = b && p.valid && intersect_box(p, *b, p.tmax, &entry);
                ASSERT_EQ(ok[i], want ? 1 : 0) << "n " << n << " ray " << i;
                if (!b) continue;
                invalid += !p.valid;
                if (!want) {
                    missed += p.valid;
                    continue;
                }
                ++ok_count;
                const Vec3 ad{std::fabs(p.dir.x), std::fabs(p.dir.y), std::fabs(p.dir.z)};
                ties += ad[p.kz] == ad[(p.kz + 1) % 3] || ad[p.kz] == ad[(p.kz + 2) % 3];
                rescaled += p.t_exp != 0;
                flushed += (p.dir.x == 0.0f) != (rays[i].dir.x == 0.0f) || (p.dir.y == 0.0f) != (rays[i].dir.y == 0.0f);
                negative_tmin += p.tmin < 0.0f;
                const PreparedRay& q = out[i];
                for (int k = 0; k < 3; ++k) {
                    ASSERT_EQ(bits_of(q.org[k]), bits_of(p.org[k])) << "ray " << i;
                    ASSERT_EQ(bits_of(q.dir[k]), bits_of(p.dir[k])) << "ray " << i;
                    ASSERT_EQ(bits_of(q.rdir[k]), bits_of(p.rdir[k])) << "ray " << i;
                }
                ASSERT_EQ(bits_of(q.tmin), bits_of(p.tmin)) << "ray " << i;
                ASSERT_EQ(bits_of(q.tmax), bits_of(p.tmax)) << "ray " << i;
                ASSERT_EQ(q.near_x, p.near_x) << "ray " << i;
                ASSERT_EQ(q.near_y, p.near_y) << "ray " << i;
                ASSERT_EQ(q.near_z, p.near_z) << "ray " << i;
                ASSERT_EQ(q.octant, p.octant) << "ray " << i;
                ASSERT_EQ(q.kx, p.kx) << "ray " << i;
                ASSERT_EQ(q.ky, p.ky) << "ray " << i;
                ASSERT_EQ(q.kz, p.kz) << "ray " << i;
                ASSERT_EQ(bits_of(q.sx), bits_of(p.sx)) << "ray " << i;
                ASSERT_EQ(bits_of(q.sy), bits_of(p.sy)) << "ray " << i;
                ASSERT_EQ(bits_of(q.sz), bits_of(p.sz)) << "ray " << i;
                ASSERT_EQ(q.valid, p.valid) << "ray " << i;
                ASSERT_EQ(q.t_exp, p.t_exp) << "ray " << i;
                ASSERT_EQ(bits_of(q.far_slack), bits_of(p.far_slack)) << "ray " << i;
            }
        }
    }
    // The cases above occurred among the rays that hit the bounds.
    EXPECT_GT(ok_count, 200);
    EXPECT_GT(missed, 50);
    EXPECT_GT(invalid, 20);
    EXPECT_GT(ties, 20);
    EXPECT_GT(rescaled, 10);
    EXPECT_GT(flushed, 5);
    EXPECT_GT(negative_tmin, 20);
}

TEST_P(KernelsVsScalar, Box8Random) {
    Rng rng(1);
    for (int blk = 0; blk < 300; ++blk) {
        Box8 box;
        box.clear();
        const int n = 1 + rng.below(8);
        for (int j = 0; j < n; ++j) box.set(rng.below(8), random_box(rng));
        std::vector<Ray> rays;
        for (int i = 0; i < 64; ++i) {
            Ray r = random_ray(rng, 2.5f);
            if (rng.chance(0.3f)) {  // origin exactly on a slab plane of some box
                const Aabb b = box.get(rng.below(8));
                const int axis = rng.below(3);
                const float plane = rng.chance(0.5f) ? b.lo[axis] : b.hi[axis];
                if (std::isfinite(plane)) r.org[axis] = plane;
                if (rng.chance(0.5f)) r.dir[axis] = rng.chance(0.5f) ? 0.0f : -0.0f;
                if (r.dir.x == 0 && r.dir.y == 0 && r.dir.z == 0) r.dir.x = 1;
            }
            rays.push_back(r);
        }
        check_box8(rays, box, "random");
        if (HasFatalFailure()) return;
    }
}

TEST_P(KernelsVsScalar, Box8AxisAlignedSignedZeroAndSlabPlanes) {
    Box8 box;
    box.clear();
    box.set(0, {{0, 0, 0}, {1, 1, 1}});
    box.set(1, {{-1, 0, 0}, {0, 0, 1}});                   // flat in y
    box.set(2, {{0.5f, 0.5f, 0.5f}, {0.5f, 0.5f, 0.5f}});  // a point
    box.set(3, {{-kInf, -1, -1}, {kInf, 1, 1}});           // infinite slab
    box.set(5, {{2, 2, 2}, {3, 3, 3}});
    box.set(7, {{-1e30f, -1e-30f, 0}, {1e30f, 1e-30f, 1e-38f}});
    std::vector<Ray> rays;
    const float planes[] = {-1, 0, -0.0f, 0.5f, 1, 2, 3, 1e-30f, -1e-30f};
    const float zeros[] = {0.0f, -0.0f};
    for (int axis = 0; axis < 3; ++axis)
        for (float s : {1.0f, -1.0f})
            for (float z1 : zeros)
                for (float z2 : zeros)
                    for (float p : planes)
                        for (float q : planes) {
                            Ray r;
                            r.dir[axis] = s;
                            r.dir[(axis + 1) % 3] = z1;
                            r.dir[(axis + 2) % 3] = z2;
                            r.org[axis] = -5 * s;
                            r.org[(axis + 1) % 3] = p;
                            r.org[(axis + 2) % 3] = q;
                            rays.push_back(r);
                            r.org[axis] = p;  // origin on a plane along the ray axis too
                            rays.push_back(r);
                        }
    check_box8(rays, box, "axis-aligned");
    // Semantics: a ray along +x through y = z = 0.5 hits box 0 and the point box 2.
    std::vector<Ray> one{Ray{{-5, 0.5f, 0.5f}, 0, {1, -0.0f, 0.0f}, kInf}};
    std::vector<std::uint8_t> m(1);
    std::vector<float> e(8);
    kernels::intersect_box8(one, box, m, e, GetParam());
    EXPECT_EQ(m[0] & 0x7, 0x5);
    EXPECT_EQ(e[0], 5.0f);
}

TEST_P(KernelsVsScalar, Box8InvalidRaysMiss) {
    Box8 box;
    box.clear();
    for (int j = 0; j < 8; ++j) box.set(j, {{-10, -10, -10}, {10, 10, 10}});
    const std::vector<Ray> rays = {
        Ray{{0, 0, 0}, 0, {0, 0, 0}, kInf},
        Ray{{kNaN, 0, 0}, 0, {1, 0, 0}, kInf},
        Ray{{0, 0, 0}, 0, {kNaN, 1, 0}, kInf},
        Ray{{0, kInf, 0}, 0, {1, 0, 0}, kInf},
        Ray{{0, 0, 0}, 0, {1, kInf, 0}, kInf},
        Ray{{0, 0, 0}, kNaN, {1, 0, 0}, kInf},
        Ray{{0, 0, 0}, 0, {1, 0, 0}, kNaN},
        Ray{{0, 0, 0}, 2, {1, 0, 0}, 1},
        Ray{{0, 0, 0}, 0, {-0.0f, 0.0f, -0.0f}, kInf},
    };
    check_box8(rays, box, "invalid");
    std::vector<std::uint8_t> m(rays.size());
    std::vector<float> e(8 * rays.size());
    kernels::intersect_box8(rays, box, m, e, GetParam());
    for (std::size_t i = 0; i < rays.size(); ++i) {
        EXPECT_EQ(m[i], 0) << "ray " << i;
        for (int j = 0; j < 8; ++j) EXPECT_EQ(e[8 * i + j], kInf);
    }
}

// Directions prepare() rescales (subnormal and huge: collect_boxes tests
// those rays one at a time), subnormal components of other directions
// (flushed to signed zeros), negative tmin whose far slack decides hits, and
// a ray count that is no multiple of 8.
TEST_P(KernelsVsScalar, Box8RescaledAndSubnormalDirectionsNegativeTmin) {
    Rng rng(11);
    const float scales[] = {1.0f, 0x1p-40f, 0x1p-135f, 0x1p126f};
    int rescaled_hits = 0, rescale_matters = 0, slack_matters = 0;
    for (int blk = 0; blk < 40; ++blk) {
        Box8 box;
        box.clear();
        for (int j = 0; j < 8; ++j) box.set(j, random_box(rng));
        std::vector<Ray> rays;
        for (int i = 0; i < 61; ++i) {
            Ray r = random_ray(rng, 2.5f);
            const float s = scales[rng.below(4)];
            r.dir = Vec3{r.dir.x * s, r.dir.y * s, r.dir.z * s};
            if (rng.chance(0.2f)) {  // subnormal: the flushed zero's 1 / 0 = inf differs from 1 / 0x1.8p-127
                r.dir.y = rng.chance(0.5f) ? 0x1.8p-127f : 1e-40f;
                if (rng.chance(0.5f)) r.dir.y = -r.dir.y;
                if (rng.chance(0.5f)) r.org.y = box.get(rng.below(8)).lo.y;  // 0 * inf: NaN, the slab order decides
            }
            if (r.dir.x == 0 && r.dir.y == 0 && r.dir.z == 0) r.dir.z = s;
            if (s != 1.0f) r.tmax = kInf;  // t scales with 1 / s
            if (rng.chance(0.3f)) r.tmin = -rng.range(0, 3) * (rng.chance(0.5f) ? 1e6f : 1.0f);
            rays.push_back(r);
            const PreparedRay p = prepare(r);
            PreparedRay unscaled = p, no_slack = p;  // as if prepare() skipped either step
            unscaled.dir = r.dir;
            auto rcp = [](float d) { return d != 0.0f ? 1.0f / d : std::copysign(kInf, d); };
            unscaled.rdir = {rcp(r.dir.x), rcp(r.dir.y), rcp(r.dir.z)};
            unscaled.tmin = r.tmin;
            unscaled.tmax = r.tmax;
            no_slack.far_slack = 0.0f;
            for (int j = 0; j < 8 && p.valid; ++j) {
                float e, e1;
                const bool hit = intersect_box(p, box.get(j), p.tmax, &e);
                rescaled_hits += hit && p.t_exp != 0;
                rescale_matters += p.t_exp != 0 && (hit != intersect_box(unscaled, box.get(j), r.tmax, &e1) ||
                                                    (hit && bits_of(to_caller_t(p, e)) != bits_of(e1)));
                slack_matters += hit != intersect_box(no_slack, box.get(j), p.tmax, &e1);
            }
        }
        check_box8(rays, box, "rescaled");
        if (HasFatalFailure()) return;
    }
    // The cases above occur, and change what the rays hit.
    EXPECT_GT(rescaled_hits, 100);
    EXPECT_GT(rescale_matters, 20);
    EXPECT_GT(slack_matters, 20);
}

// collect_boxes tests a ray against a group of 8 boxes only when it hits the
// group's union (the super box, batch-inl.h). A NaN coordinate makes the box
// test discard that slab plane (the box is unbounded there), so a union that
// dropped the NaN would skip hits: here boxes with NaN planes sit in groups
// with boxes elsewhere, and every ray's boxes and entries must still be
// intersect_box's, on every ISA.
TEST_P(KernelsVsScalar, CollectBoxesWithNanPlanes) {
    Rng rng(23);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::vector<Aabb> boxes;
    for (int b = 0; b < 40; ++b) boxes.push_back(random_box(rng));
    boxes[0] = {{nan, 0, 0}, {1, 1, 1}};  // unbounded below in x
    boxes[1] = {{5, 5, 5}, {6, 6, 6}};
    boxes[9] = {{0, 0, 0}, {1, nan, 1}};  // unbounded above in y
    boxes[10] = {{-6, -6, -6}, {-5, -5, -5}};
    boxes[17] = {{nan, nan, nan}, {nan, nan, nan}};
    std::vector<Ray> rays;
    for (int i = 0; i < 197; ++i) rays.push_back(random_ray(rng, 2.5f));
    rays.push_back(Ray{{0.5f, 0.5f, 0.5f}, 0.0f, {-1, 0, 0}, kInf});  // into box 0's open side, away from box 1
    rays.push_back(Ray{{0.5f, 0.5f, 0.5f}, 0.0f, {0, 1, 0}, kInf});   // into box 9's open side
    rays.push_back(Ray{{0.5f, 40.0f, 0.5f}, 0.0f, {0, -1, 0}, kInf});
    std::size_t nan_hits = 0;
    std::vector<std::vector<std::pair<float, std::uint32_t>>> want(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const PreparedRay p = prepare(rays[i]);
        for (std::size_t b = 0; b < boxes.size() && p.valid; ++b) {
            float e;
            if (!intersect_box(p, boxes[b], p.tmax, &e)) continue;
            want[i].push_back({to_caller_t(p, e), std::uint32_t(b)});
            nan_hits += b == 0 || b == 9 || b == 17;
        }
    }
    EXPECT_GE(nan_hits, 3u);
    for (Isa run : {Isa::scalar, GetParam()}) {
        std::vector<std::pair<float, std::uint32_t>> out;
        std::vector<std::uint32_t> first(rays.size() + 1);
        kernels::collect_boxes(rays, {}, boxes, out, first, run);
        for (std::size_t i = 0; i < rays.size(); ++i) {
            ASSERT_EQ(first[i + 1] - first[i], want[i].size()) << name(run) << " ray " << i;
            for (std::size_t k = 0; k < want[i].size(); ++k) {
                EXPECT_EQ(out[first[i] + k].second, want[i][k].second) << name(run) << " ray " << i;
                EXPECT_EQ(bits_of(out[first[i] + k].first), bits_of(want[i][k].first)) << name(run) << " ray " << i;
            }
        }
    }
}

// ---------- triangles ----------

Vec3 on_triangle(Rng& rng, const Tri1& t) {
    float u = rng.uniform(), v = rng.uniform();
    switch (rng.below(6)) {
    case 0:
        u = float(rng.below(2));
        v = u == 1 ? 0.0f : float(rng.below(2));
        break;                 // a vertex
    case 1: v = 0; break;      // on edge v0-v1
    case 2: u = 0; break;      // on edge v0-v2
    case 3: v = 1 - u; break;  // on edge v1-v2 (approximately)
    default:
        if (u + v > 1) {
            u = 1 - u;
            v = 1 - v;
        }
    }
    return t.v0 + (t.v1 - t.v0) * u + (t.v2 - t.v0) * v;
}

std::vector<Tri1> random_soup(Rng& rng, int n, float size) {
    std::vector<Tri1> tris;
    for (int i = 0; i < n; ++i) {
        const Vec3 c = rng.in_box(-1, 1);
        Tri1 t{c + rng.in_box(-size, size), c + rng.in_box(-size, size), c + rng.in_box(-size, size),
               std::uint32_t(i * 7 % 1000)};
        if (rng.chance(0.15f) && i > 0) t.v0 = tris[rng.below(i)].v1;  // shared vertices
        tris.push_back(t);
    }
    return tris;
}

std::vector<Ray> rays_at(Rng& rng, const std::vector<Tri1>& tris, int n) {
    std::vector<Ray> rays;
    for (int i = 0; i < n; ++i) {
        Ray r = random_ray(rng, 3);
        if (rng.chance(0.8f)) {
            const Vec3 target = on_triangle(rng, tris[rng.below(int(tris.size()))]);
            r.dir = target - r.org;
            if (rng.chance(0.2f)) {  // axis-aligned towards the target
                const int a = rng.below(3);
                r.org = target;
                r.org[a] -= 2;
                r.dir = Vec3{};
                r.dir[a] = 1;
                r.dir[(a + 1) % 3] = rng.chance(0.5f) ? 0.0f : -0.0f;
            }
            if (r.dir.x == 0 && r.dir.y == 0 && r.dir.z == 0) r.dir = {0, 0, 1};
            r.tmin = 0;
        }
        rays.push_back(r);
    }
    return rays;
}

TEST_P(KernelsVsScalar, Tri8Random) {
    Rng rng(2);
    int hits = 0;
    for (int round = 0; round < 40; ++round) {
        std::vector<Tri1> tris =
            random_soup(rng, 8 * (1 + rng.below(6)) - rng.below(8), rng.chance(0.5f) ? 0.7f : 0.05f);
        std::vector<Tri8> blocks = test::pack_tri8(tris);
        std::vector<Ray> rays = rays_at(rng, tris, 200);
        std::vector<Hit> closest;
        check_tri8(rays, blocks, "random", &closest);
        if (HasFatalFailure()) return;
        // tmax exactly at the hit distance still hits (closed interval), just below misses that triangle.
        for (std::size_t i = 0; i < rays.size(); ++i)
            if (closest[i].hit()) {
                ++hits;
                rays[i].tmax = closest[i].t;
            }
        std::vector<Hit> again;
        check_tri8(rays, blocks, "tmax = t", &again);
        if (HasFatalFailure()) return;
        for (std::size_t i = 0; i < rays.size(); ++i) ASSERT_EQ(again[i], closest[i]) << "ray " << i;
    }
    EXPECT_GT(hits, 1000) << "the random rays should mostly hit";
}

TEST_P(KernelsVsScalar, Tri8VerticesAndEdgesOfAClosedFan) {
    // A fan of triangles around the origin in z = 0 with shared vertices and
    // edges; rays aimed at every vertex and edge midpoint from many origins.
    std::vector<Tri1> tris;
    const int n = 12;
    std::vector<Vec3> ring;
    for (int k = 0; k < n; ++k)
        ring.push_back({std::cos(6.2831853f * k / n), std::sin(6.2831853f * k / n), 0.25f * float(k % 3)});
    const Vec3 hub{0.1f, -0.05f, 0.3f};
    for (int k = 0; k < n; ++k) tris.push_back({hub, ring[k], ring[(k + 1) % n], std::uint32_t(100 + k)});
    const std::vector<Tri8> blocks = test::pack_tri8(tris);
    std::vector<Vec3> targets{hub};
    for (int k = 0; k < n; ++k) {
        targets.push_back(ring[k] * 0.999f + hub * 0.001f);
        targets.push_back((hub + ring[k]) * 0.5f);
        targets.push_back((ring[k] + ring[(k + 1) % n]) * 0.49f + hub * 0.02f);  // near the rim, inside
        targets.push_back(hub * 0.5f + ring[k] * 0.25f + ring[(k + 1) % n] * 0.25f);
    }
    Rng rng(3);
    std::vector<Ray> rays;
    for (const Vec3& t : targets)
        for (int i = 0; i < 24; ++i) {
            Vec3 o = rng.in_box(-2, 2);
            o.z = rng.chance(0.5f) ? 3 : -3;
            if (i < 6) o = {t.x, t.y, i % 2 ? 2.0f : -2.0f};  // along +-z exactly
            rays.push_back(Ray{o, 0, t - o, kInf});
        }
    std::vector<Hit> closest;
    check_tri8(rays, blocks, "fan", &closest);
    if (HasFatalFailure()) return;
    // Watertight: every ray aimed at an interior vertex or edge hits something.
    for (std::size_t i = 0; i < rays.size(); ++i) EXPECT_TRUE(closest[i].hit()) << "watertight leak, ray " << i;
}

TEST_P(KernelsVsScalar, Tri8RaysAlongEdgesAndCoplanar) {
    const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0};
    std::vector<Tri1> tris{{a, b, c, 1}, {b, {1, 1, 0}, c, 2}, {a, b, {0.5f, 0, 1}, 3}};
    const std::vector<Tri8> blocks = test::pack_tri8(tris);
    std::vector<Ray> rays;
    for (const auto& [p, q] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}, std::pair{a, Vec3{1, 1, 0}}}) {
        rays.push_back(Ray{p - (q - p), 0, q - p, kInf});                 // along the edge line
        rays.push_back(Ray{p, 0, q - p, kInf});                           // from a vertex along the edge
        rays.push_back(Ray{(p + q) * 0.5f, 0, q - p, kInf});              // from the middle of the edge
        rays.push_back(Ray{p + Vec3{0, 0, 1}, 0, Vec3{0, 0, -1}, kInf});  // down onto the vertex
        rays.push_back(Ray{(p + q) * 0.5f + Vec3{0, 0, -1}, 0, Vec3{0, -0.0f, 1}, kInf});  // up through the edge
    }
    rays.push_back(Ray{{-1, 0.25f, 0}, 0, {1, 0, 0}, kInf});  // coplanar, crossing the interior
    check_tri8(rays, blocks, "edges");
    if (HasFatalFailure()) return;
    // Exactly through the shared edge b-c (an edge function is exactly 0: the
    // exact path): watertight hits, both triangles at the same t, lower id wins.
    std::vector<Ray> through{Ray{{0.5f, 0.5f, -1}, 0, {0, -0.0f, 1}, kInf},
                             Ray{{0.5f, 0.5f, 1}, 0, {0.0f, 0, -1}, kInf}, Ray{{0.25f, 0.75f, -2}, 0, {0, 0, 2}, kInf}};
    std::vector<Hit> h(through.size());
    kernels::intersect_tri8(through, blocks, TriangleTest::watertight, h, GetParam());
    for (std::size_t i = 0; i < through.size(); ++i) EXPECT_EQ(h[i].prim, 1u) << "ray " << i << " " << hit_str(h[i]);
}

TEST_P(KernelsVsScalar, Tri8DegenerateTrianglesMiss) {
    const Vec3 p{0.2f, 0.3f, 0}, q{0.7f, 0.1f, 0}, r{0.3f, 0.9f, 0};
    std::vector<Tri1> tris{{p, p, q, 1}, {p, q, q, 2}, {q, p, q, 3}, {p, p, p, 4}, {r, q, r, 5}};
    const std::vector<Tri8> blocks = test::pack_tri8(tris);
    std::vector<Ray> rays;
    for (const Vec3& t : {p, q, r, (p + q) * 0.5f, (p + r) * 0.5f})
        for (const Vec3& o : {Vec3{0, 0, -1}, Vec3{0.5f, 0.5f, 1}, Vec3{t.x, t.y, -2}, Vec3{-1, 0.2f, 0}})
            rays.push_back(Ray{o, 0, t - o, kInf});
    for (TriangleTest test : kTests) {
        std::vector<Hit> h;
        check_tri8(rays, blocks, "degenerate", &h, test, true);
        if (HasFatalFailure()) return;
        for (std::size_t i = 0; i < rays.size(); ++i)
            EXPECT_FALSE(h[i].hit()) << test_name(test) << ": degenerate triangle hit, ray " << i << " "
                                     << hit_str(h[i]);
    }
}

TEST_P(KernelsVsScalar, Tri8NanInfRaysAndVertices) {
    std::vector<Tri1> tris{
        {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}, 1},
        {{kNaN, -1, 1}, {1, -1, 1}, {0, 1, 1}, 2},
        {{-1, -1, 2}, {kInf, -1, 2}, {0, 1, 2}, 3},
        {{-1, -1, 3}, {1, -1, 3}, {0, -kInf, 3}, 4},
        {{-kInf, -kInf, 4}, {kInf, -kInf, 4}, {0, kInf, 4}, 5},
        {{-1, -1, 5}, {1, -1, 5}, {0, 1, kInf}, 6},
        {{-1e38f, -1e38f, 6}, {3e38f, -1e38f, 6}, {0, 3e38f, 6}, 7},  // overflow in the edge functions
        {{-1, -1, 7}, {1, -1, 7}, {kNaN, kNaN, kNaN}, 8},
        {{-1, -1, -1}, {1, -1, -1}, {0, 1, -1}, 9},
    };
    const std::vector<Tri8> blocks = test::pack_tri8(tris);
    std::vector<Ray> rays;
    for (float z : {-10.0f, 0.5f, 1.5f, 2.5f, 3.5f, 4.5f, 5.5f, 6.5f, 10.0f})
        for (float dz : {1.0f, -1.0f}) {
            rays.push_back(Ray{{0, 0, z}, 0, {0, 0, dz}, kInf});
            rays.push_back(Ray{{0.1f, -0.2f, z}, 0, {0.01f, 0.02f, dz}, kInf});
        }
    const std::vector<Ray> bad = {
        Ray{{kNaN, 0, -10}, 0, {0, 0, 1}, kInf}, Ray{{0, 0, -10}, 0, {0, kNaN, 1}, kInf},
        Ray{{0, 0, -kInf}, 0, {0, 0, 1}, kInf},  Ray{{0, 0, -10}, 0, {0, 0, kInf}, kInf},
        Ray{{0, 0, -10}, 0, {0, 0, 0}, kInf},    Ray{{0, 0, -10}, 0, {-0.0f, 0.0f, -0.0f}, kInf},
        Ray{{0, 0, -10}, kNaN, {0, 0, 1}, kInf}, Ray{{0, 0, -10}, 0, {0, 0, 1}, kNaN},
        Ray{{0, 0, -10}, 5, {0, 0, 1}, 4},
    };
    rays.insert(rays.end(), bad.begin(), bad.end());
    std::vector<Hit> h;
    check_tri8(rays, blocks, "nan/inf", &h);
    for (std::size_t i = rays.size() - bad.size(); i < rays.size(); ++i)
        EXPECT_EQ(h[i], Hit{}) << "invalid ray " << i << " must miss";
    EXPECT_EQ(h[0].prim, 9u);  // from z = -10 upwards: the valid triangle at z = -1
}

TEST_P(KernelsVsScalar, Tri8EmptySlots) {
    Rng rng(4);
    for (int filled = 0; filled <= 8; ++filled) {
        std::vector<Tri1> tris = random_soup(rng, filled, 0.8f);
        std::vector<Tri8> blocks(1);
        blocks[0].clear();
        std::vector<Ray> rays;
        for (int i = 0; i < filled; ++i) {
            const int lane = (i * 3 + filled) % 8;  // scattered lanes
            blocks[0].set(lane, tris[i].v0, tris[i].v1, tris[i].v2, tris[i].prim);
        }
        if (filled > 0) rays = rays_at(rng, tris, 100);
        for (int i = 0; i < 20; ++i) rays.push_back(random_ray(rng, 3));
        std::vector<Hit> h;
        check_tri8(rays, blocks, "empty slots", &h);
        if (HasFatalFailure()) return;
        for (const Hit& x : h)
            if (x.hit()) {
                EXPECT_NE(x.prim, kInvalidPrim);
            }
    }
}

TEST_P(KernelsVsScalar, Tri8TiesGoToTheLowerPrim) {
    const Vec3 a{-1, -1, 0}, b{1, -1, 0}, c{0, 1, 0};
    std::vector<Tri8> blocks(2);
    blocks[0].clear();
    blocks[1].clear();
    blocks[0].set(0, a, b, c, 9);  // same triangle, higher id, lower lane
    blocks[0].set(5, a, b, c, 3);
    blocks[1].set(2, a, b, c, 2);  // later block, lowest id
    std::vector<Ray> rays{Ray{{0, 0, -1}, 0, {0, 0, 1}, kInf}, Ray{{0.2f, -0.3f, 2}, 0, {0.01f, 0.02f, -1}, kInf},
                          Ray{{0, 0, -1}, 0, {0, 0, 1}, 1.0f}};
    check_tri8(rays, blocks, "ties");
    for (TriangleTest test : kTests) {
        std::vector<Hit> h(rays.size());
        kernels::intersect_tri8(rays, blocks, test, h, GetParam());
        for (const Hit& x : h) EXPECT_EQ(x.prim, 2u) << test_name(test);
        std::span<const Tri8> first(&blocks[0], 1);
        kernels::intersect_tri8(rays, first, test, h, GetParam());
        for (const Hit& x : h) EXPECT_EQ(x.prim, 3u) << test_name(test) << " within one block";
        // Any hit: the first lane that hits (lane 0, prim 9).
        std::vector<std::uint8_t> occ(rays.size());
        kernels::occluded_tri8(rays, blocks, test, occ, h, GetParam());
        for (const Hit& x : h) EXPECT_EQ(x.prim, 9u) << test_name(test);
    }
}

TEST(Kernels, SingleFormsMatchTheReference) {
    Rng rng(5);
    std::vector<Tri1> tris = random_soup(rng, 64, 0.7f);
    std::vector<Ray> rays = rays_at(rng, tris, 64);
    std::vector<Hit> hits(64);
    for (TriangleTest test : kTests) {
        kernels::intersect_tri1(rays, tris, test, hits);
        for (int i = 0; i < 64; ++i) {
            const PreparedRay p = prepare(rays[i]);
            float t, u, v;
            const bool h = test == TriangleTest::watertight
                               ? intersect_watertight(p, tris[i].v0, tris[i].v1, tris[i].v2, p.tmax, &t, &u, &v)
                               : intersect_moller(p, tris[i].v0, tris[i].v1, tris[i].v2, p.tmax, &t, &u, &v);
            const Hit want = h ? Hit{t, u, v, tris[i].prim} : Hit{};
            EXPECT_EQ(hits[i], want);
        }
    }
    std::vector<Aabb> boxes;
    for (int i = 0; i < 64; ++i) boxes.push_back(random_box(rng));
    std::vector<std::uint8_t> m(64);
    std::vector<float> e(64);
    kernels::intersect_box1(rays, boxes, m, e);
    for (int i = 0; i < 64; ++i) {
        const PreparedRay p = prepare(rays[i]);
        float x;
        EXPECT_EQ(m[i] != 0, intersect_box(p, boxes[i], p.tmax, &x));
        if (m[i]) {
            EXPECT_EQ(bits_of(e[i]), bits_of(x));
        }
    }
}

TEST(Kernels, SpanSizesAreChecked) {
    std::vector<Ray> rays(4);
    std::vector<Hit> hits(3);
    EXPECT_THROW(kernels::intersect_tri8(rays, {}, TriangleTest::watertight, hits, Isa::scalar), Error);
    Box8 box;
    box.clear();
    std::vector<std::uint8_t> m(4);
    std::vector<float> e(31);
    EXPECT_THROW(kernels::intersect_box8(rays, box, m, e, Isa::scalar), Error);
}

// prepare_scaled() is prepare()'s first stage: the same org, dir, tmin, tmax,
// t_exp and valid bits for ordinary, tiny, huge, subnormal and invalid rays.
TEST(PrepareScaled, SameFirstStageAsPrepare) {
    const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    const float sub = std::numeric_limits<float>::denorm_min();
    const std::vector<Ray> rays = {
        {{1, 2, 3}, 0.0f, {0.5f, -0.25f, 1.0f}, inf},
        {{1, 2, 3}, -2.0f, {1e-30f, 3e-31f, -2e-30f}, 1e30f},  // rescaled up
        {{0, 0, 0}, 0.0f, {1e30f, -3e30f, 2e29f}, 5.0f},       // rescaled down
        {{0, 0, 0}, 0.0f, {1.0f, sub, -sub}, inf},             // subnormal components flushed
        {{0, 0, 0}, 0.0f, {0.0f, 0.0f, 0.0f}, inf},            // invalid: zero direction
        {{nan, 0, 0}, 0.0f, {1.0f, 0.0f, 0.0f}, inf},          // invalid: NaN origin
        {{0, 0, 0}, 2.0f, {1.0f, 0.0f, 0.0f}, 1.0f},           // invalid: empty interval
    };
    auto bits = [](float f) {
        std::uint32_t b;
        std::memcpy(&b, &f, 4);
        return b;
    };
    int rescaled = 0;
    for (const Ray& r : rays) {
        const PreparedRay a = prepare(r), b = prepare_scaled(r);
        for (int k = 0; k < 3; ++k) {
            EXPECT_EQ(bits(a.org[k]), bits(b.org[k]));
            EXPECT_EQ(bits(a.dir[k]), bits(b.dir[k]));
        }
        EXPECT_EQ(bits(a.tmin), bits(b.tmin));
        EXPECT_EQ(bits(a.tmax), bits(b.tmax));
        EXPECT_EQ(a.t_exp, b.t_exp);
        EXPECT_EQ(a.valid, b.valid);
        rescaled += a.t_exp != 0;
    }
    EXPECT_EQ(rescaled, 2);
    EXPECT_EQ(prepare_scaled(rays[3]).dir.y, 0.0f);
    EXPECT_FALSE(prepare_scaled(rays[4]).valid);
    EXPECT_FALSE(prepare_scaled(rays[6]).valid);
}

INSTANTIATE_TEST_SUITE_P(AllIsas, KernelsVsScalar, testing::ValuesIn(kAllIsas), test::isa_param_name);

}  // namespace
}  // namespace simdbvh
