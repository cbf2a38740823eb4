// Step 1 of the wide BVH build: collapse the BVH2 into a tree of up to N
// children per node (N = 4, 8, 16; the tables have N columns).
//
// SAH (Ylitie, Karras, Laine 2017, "Efficient Incoherent Ray Traversal on
// GPUs Through Compressed Wide BVHs", section 4): a bottom-up dynamic program
// over the BVH2 computes, per node n and slot budget i = 1..N, the cheapest way
// C(n, i) to represent n's subtree as at most i children of a wide node:
//   C(n, 1) = min(C_leaf(n), C_internal(n)),  C_internal(n) = C_dist(n, N) + Ct * A(n)
//   C(n, i) = min(C_dist(n, i), C(n, i - 1))
//   C_dist(n, j) = min_k C(left, k) + C(right, j - k)
// Leaf cost adapted to our leaf format: a leaf is tested one whole Tri8 block
// at a time, so n triangles cost Cb * ceil(n / kBlockWidth) * A(n) (block_cost Cb; small
// leaves share blocks with their siblings in memory, pack.cpp, but a visit
// still tests one whole block), and
// C_leaf = inf above max_leaf_size (a BVH2 leaf that is already larger is kept).
//
// Greedy: start from the two children of a BVH2 node and repeatedly replace the
// one with the largest surface area by its two children until there are N or
// none can be opened. A subtree that fits one Tri8 block (<= min(kBlockWidth,
// max_leaf_size) triangles) becomes a leaf. Every greedy tree is a candidate of
// the dynamic program, so the SAH collapse never costs more under this model.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <span>
#include <string>
#include <type_traits>

#include "simdbvh/bvh8/internal/collapse.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/platform/large_alloc.h"
#include "simdbvh/platform/parallel.h"

namespace simdbvh::bvh8 {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

double blocks_of(std::uint32_t n) { return double((n + kBlockWidth - 1u) / kBlockWidth); }

template <int N>
struct Collapser {
    std::size_t prims;  // triangles in the BVH2's leaves
    const WideOptions& opts;
    std::span<const Node2> n2;
    LargeVector<std::uint32_t> prim_count;  // triangles under each BVH2 node (greedy only)
    // SAH tables (index i - 1 for i = 1..N). The costs C(n, i) live only on
    // the recursion (a parent needs its children's), not in a table per node.
    using Costs = std::array<double, N>;
    Costs root_left{}, root_right{};                // C(left(0), .), C(right(0), .): the root's leaf test
    LargeVector<std::array<std::uint8_t, N>> from;  // i >= 2: 0 = same as i - 1, k = C_dist split (k left slots)
    LargeVector<std::uint8_t> distn;                // split of C_dist(n, N) (the children of an inner node)
    LargeVector<std::uint8_t> leaf1;                // C(n, 1) is a leaf
    WideTopology<N> topo;

    Collapser(std::span<const Node2> nodes, std::size_t p, const WideOptions& o) : prims(p), opts(o), n2(nodes) {}

    std::uint32_t left(std::uint32_t n) const { return n2[n].first; }
    std::uint32_t right(std::uint32_t n) const { return n2[n].first + 1; }

    bool leafable(std::uint32_t count) const { return count <= std::uint32_t(opts.max_leaf_size); }

    // Areas as the float collapse computed them when the root's float area is
    // finite (every box lies inside it: the same trees, bit for bit), else in
    // double (finite for any finite mesh: no cost is +inf).
    bool float_areas = true;
    double area(std::uint32_t n) const {
        return float_areas ? double(n2[n].box.half_area_float()) : n2[n].box.half_area();
    }

    double leaf_cost(std::uint32_t n, std::uint32_t count) const {
        return double(opts.block_cost) * blocks_of(count) * area(n);
    }

    // Whether every BVH2 subtree's leaves are contiguous in the leaf order,
    // left before right, as make_leaf needs: checked on the way up (a right
    // subtree must begin where the left one ends).
    std::atomic<bool> contiguous{true};
    void check_adjacent(std::uint32_t left_begin, std::uint32_t left_count, std::uint32_t right_begin) {
        if (left_begin + left_count != right_begin) contiguous.store(false, std::memory_order_relaxed);
    }

    // Triangles under n, and the first one's position in the leaf order
    // (recursion depth <= the BVH2's depth <= kMaxDepth).
    std::uint32_t count_prims(std::uint32_t n, std::uint32_t& begin) {
        const Node2& nd = n2[n];
        if (nd.is_leaf()) {
            begin = nd.first;
            return prim_count[n] = nd.count;
        }
        std::uint32_t br = 0;
        const std::uint32_t nl = count_prims(left(n), begin), nr = count_prims(right(n), br);
        check_adjacent(begin, nl, br);
        return prim_count[n] = nl + nr;
    }

    // C(n, 1..N) bottom-up; records from, distn and leaf1 for n (every
    // node, leaves included: the tables are not zeroed beforehand, and this
    // pass, parallel, is their first touch). The top `spawn` levels solve
    // their right child on another thread: every node writes only its own
    // entries, so the tables do not depend on the thread count.
    // `count`: triangles under n, counted on the way up; `begin`: the first
    // one's position in the leaf order.
    //
    // `leaves`: BVH2 leaves under n (L). No representation uses more than L
    // slots, so C(n, i) = C(n, L) for i >= L: C_dist(n, j) for L < j < N
    // only repeats sums of smaller budgets (never strictly smaller: the same
    // "same as i - 1" entries) and is not computed; C_dist(n, N) always is.
    Costs solve_sah(std::uint32_t n, int spawn, std::uint32_t& leaves, std::uint32_t& count, std::uint32_t& begin) {
        Costs c;
        if (n2[n].is_leaf()) {
            count = n2[n].count;
            begin = n2[n].first;
            c.fill(leaf_cost(n, count));
            from[n] = {};
            distn[n] = 0;
            leaf1[n] = 1;
            leaves = 1;
            return c;
        }
        Costs cl, cr;
        std::uint32_t ll = 0, lr = 0, nl = 0, nr = 0, br = 0;
        if (spawn > 0) {  // the two sides as tasks (the host executor's, or threads)
            run_tasks(2, [&](std::size_t k) {
                if (k == 0) cl = solve_sah(left(n), spawn - 1, ll, nl, begin);
                else cr = solve_sah(right(n), spawn - 1, lr, nr, br);
            });
        } else {
            cl = solve_sah(left(n), 0, ll, nl, begin);
            cr = solve_sah(right(n), 0, lr, nr, br);
        }
        check_adjacent(begin, nl, br);
        leaves = ll + lr;
        count = nl + nr;
        const int budget = int(std::min<std::uint32_t>(leaves, N));  // slots worth computing
        if (n == 0) {
            root_left = cl;
            root_right = cr;
        }
        // Costs are finite for finite boxes (areas in double), so a split is
        // always recorded; should one not be (all +inf), k = 1 still names
        // a valid partition of the j slots: resolve never sees slot 0.
        double dist[N + 1];
        std::uint8_t split[N + 1] = {};
        for (int j = 2; j <= N; ++j) {
            dist[j] = kInf;
            split[j] = 1;
            if (j > budget && j < N) continue;  // saturated: see above
            for (int k = 1; k < j; ++k) {       // selects, not branches (unpredictable)
                const double d = cl[k - 1] + cr[j - k - 1];
                const bool better = d < dist[j];
                dist[j] = better ? d : dist[j];
                split[j] = std::uint8_t(better ? k : split[j]);
            }
        }
        const double c_leaf = leafable(count) ? leaf_cost(n, count) : kInf;
        const double c_inner = dist[N] + double(opts.node_cost) * area(n);
        leaf1[n] = c_leaf <= c_inner;
        c[0] = std::min(c_leaf, c_inner);
        distn[n] = split[N];
        auto& f = from[n];
        f[0] = 0;
        for (int i = 2; i <= N; ++i) {
            if (i <= budget && dist[i] < c[i - 2]) {
                c[i - 1] = dist[i];
                f[i - 1] = split[i];
            } else {
                c[i - 1] = c[i - 2];
                f[i - 1] = 0;
            }
        }
        return c;
    }

    // The BVH2 nodes that fill at most i slots for n's subtree (SAH tables).
    void resolve(std::uint32_t n, int i, std::vector<std::uint32_t>& out) const {
        if (i < 1 || i > N)
            throw Error("BVH" + std::to_string(N) + " collapse: slot budget " + std::to_string(i) + " outside 1.." +
                        std::to_string(N));
        while (i > 1 && from[n][i - 1] == 0) --i;
        if (i == 1) {
            out.push_back(n);
            return;
        }
        const int k = from[n][i - 1];
        resolve(left(n), k, out);
        resolve(right(n), i - k, out);
    }

    // Greedy: open the largest-area child until N children or none can be opened.
    bool greedy_leaf(std::uint32_t n) const {
        return n2[n].is_leaf() || prim_count[n] <= std::uint32_t(std::min(kBlockWidth, opts.max_leaf_size));
    }
    void greedy_slots(std::uint32_t n, std::vector<std::uint32_t>& out) const {
        out = {left(n), right(n)};
        while (out.size() < std::size_t(N)) {
            int best = -1;
            double best_area = -1.0;
            for (int c = 0; c < int(out.size()); ++c) {
                if (greedy_leaf(out[c])) continue;
                const double a = area(out[c]);
                if (a > best_area) {
                    best_area = a;
                    best = c;
                }
            }
            if (best < 0) break;
            const std::uint32_t m = out[best];
            out[best] = left(m);
            out.insert(out.begin() + best + 1, right(m));
        }
    }

    bool slot_is_leaf(std::uint32_t n) const { return opts.collapse == Collapse::sah ? leaf1[n] != 0 : greedy_leaf(n); }
    void inner_slots(std::uint32_t n, std::vector<std::uint32_t>& out) const {
        out.clear();
        if (opts.collapse == Collapse::sah) {
            const int k = distn[n];
            resolve(left(n), k, out);
            resolve(right(n), N - k, out);
        } else {
            greedy_slots(n, out);
        }
    }

    // A leaf over n's subtree: the positions from its leftmost BVH2 leaf's
    // first to its rightmost one's end (contiguous: checked by the DP).
    WideChild make_leaf(std::uint32_t n) const {
        std::uint32_t lo = n, hi = n;
        while (!n2[lo].is_leaf()) lo = left(lo);
        while (!n2[hi].is_leaf()) hi = right(hi);
        WideChild c;
        c.box = n2[n].box;
        c.index = n2[lo].first;
        c.count = n2[hi].first + n2[hi].count - c.index;
        return c;
    }

    // Sized, not zeroed (the pass that fills a table touches it first), on
    // huge pages when large (large_alloc.h).
    template <class V>
    static void sized(V& v, std::size_t n) {
        static_assert(std::is_trivially_default_constructible_v<typename V::value_type>);
        v.resize(n);
    }

    void build() {
        float_areas = std::isfinite(n2[0].box.half_area_float());
        std::uint32_t count = 0, begin = 0;
        if (opts.collapse == Collapse::sah) {
            sized(from, n2.size());
            sized(distn, n2.size());
            sized(leaf1, n2.size());
            // Levels with tasks: one task per thread (a thread costs about
            // 0.1-0.3 ms to start on the 2-vCPU VMs measured; 2 and 4 tasks
            // per thread made the dragon's DP slower there, not faster).
            int spawn = 0;
            while (spawn < 6 && (1 << spawn) < opts.threads) ++spawn;
            std::uint32_t leaves = 0;
            solve_sah(0, opts.threads > 1 ? spawn : 0, leaves, count, begin);
        } else {
            sized(prim_count, n2.size());
            count = count_prims(0, begin);
        }
        // The leaves must cover the positions 0..prims-1 in order (make_leaf, pack).
        if (!contiguous.load() || begin != 0 || count != prims)
            throw Error("BVH" + std::to_string(N) + " collapse: the BVH2's leaves do not cover its " +
                        std::to_string(prims) + " leaf positions in order");
        topo.prims = prims;
        topo.nodes.reserve(n2.size() / 4 + 1);
        topo.nodes.emplace_back();
        topo.nodes[0].box = n2[0].box;
        // The root is always a wide node; over a single leaf when that is cheaper (or the BVH2 is one leaf).
        bool root_leaf = n2[0].is_leaf();
        if (!root_leaf) {
            if (opts.collapse == Collapse::sah) {
                root_leaf =
                    leafable(std::uint32_t(prims)) &&
                    leaf_cost(0, std::uint32_t(prims)) <= root_left[distn[0] - 1] + root_right[N - distn[0] - 1];
            } else {
                root_leaf = greedy_leaf(0);
            }
        }
        if (root_leaf) {
            topo.nodes[0].child_count = 1;
            topo.nodes[0].children[0] = make_leaf(0);
            topo.depth = 1;
            return;
        }
        struct Work {
            std::uint32_t wide, bvh2;
            int depth;
        };
        std::vector<Work> work{{0u, 0u, 1}};
        std::vector<std::uint32_t> slots;
        std::vector<Work> next;
        while (!work.empty()) {
            const Work w = work.back();
            work.pop_back();
            topo.depth = std::max(topo.depth, w.depth);
            if (w.depth > kMaxDepth)
                throw Error("BVH" + std::to_string(N) + " depth exceeds the cap " + std::to_string(kMaxDepth));
            inner_slots(w.bvh2, slots);
            next.clear();
            const std::uint32_t first = std::uint32_t(topo.nodes.size());  // the inner children's indices
            for (const std::uint32_t s : slots)
                if (!slot_is_leaf(s)) next.push_back({first + std::uint32_t(next.size()), s, w.depth + 1});
            topo.nodes.resize(topo.nodes.size() + next.size());
            WideNode<N>& node = topo.nodes[w.wide];  // written in place (a WideNode<16> is 540 bytes)
            node.box = n2[w.bvh2].box;
            node.child_count = int(slots.size());
            std::size_t inner = 0;
            for (std::size_t c = 0; c < slots.size(); ++c) {
                const std::uint32_t s = slots[c];
                WideChild& ch = node.children[c];
                if (inner < next.size() && next[inner].bvh2 == s) {
                    ch.box = n2[s].box;
                    ch.index = next[inner++].wide;
                    ch.count = 0;
                } else {
                    ch = make_leaf(s);
                }
            }
            for (auto it = next.rbegin(); it != next.rend(); ++it) work.push_back(*it);
        }
    }
};

}  // namespace

template <int N>
WideTopology<N> collapse(const Bvh2& bvh2, const WideOptions& opts) {
    return collapse<N>(bvh2.nodes(), bvh2.prim_ids().size(), opts);
}

template <int N>
WideTopology<N> collapse(std::span<const Node2> nodes, std::size_t prims, const WideOptions& opts) {
    const std::string what = "BVH" + std::to_string(N);
    if (opts.max_leaf_size < 1) throw Error(what + " max_leaf_size must be at least 1");
    if (!(opts.node_cost >= 0.0f) || !(opts.block_cost >= 0.0f) || !std::isfinite(opts.node_cost) ||
        !std::isfinite(opts.block_cost))
        throw Error(what + " node_cost and block_cost must be finite and >= 0");
    if (nodes.empty()) return {};
    Collapser<N> c(nodes, prims, opts);
    c.build();
    return std::move(c.topo);
}

template <int N>
double sah_cost(const WideTopology<N>& topo, const WideOptions& opts) {
    if (topo.nodes.empty()) return 0.0;
    // The collapse's areas: float while the root's float area is finite, else double.
    const bool fa = std::isfinite(topo.nodes[0].box.half_area_float());
    auto area = [&](const Aabb& b) { return fa ? double(b.half_area_float()) : b.half_area(); };
    double root = area(topo.nodes[0].box);
    const bool flat = !(root > 0);  // all areas zero: count tests instead
    if (flat) root = 1.0;
    double c = 0;
    for (const WideNode<N>& n : topo.nodes) {
        c += double(opts.node_cost) * (flat ? 1.0 : area(n.box)) / root;
        for (int k = 0; k < n.child_count; ++k) {
            const WideChild& ch = n.children[k];
            if (ch.is_leaf()) c += double(opts.block_cost) * blocks_of(ch.count) * (flat ? 1.0 : area(ch.box)) / root;
        }
    }
    return c;
}

#define SIMDBVH_WIDTH(N)                                                                           \
    template WideTopology<N> collapse<N>(const Bvh2&, const WideOptions&);                         \
    template WideTopology<N> collapse<N>(std::span<const Node2>, std::size_t, const WideOptions&); \
    template double sah_cost<N>(const WideTopology<N>&, const WideOptions&);
SIMDBVH_WIDTH(4)
SIMDBVH_WIDTH(8)
SIMDBVH_WIDTH(16)
#undef SIMDBVH_WIDTH

}  // namespace simdbvh::bvh8
