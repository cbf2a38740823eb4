#pragma once
// 8-wide BVH: the BVH2 collapsed by SAH cost (Ylitie, Karras, Laine 2017),
// packed into SoA nodes whose 8 child boxes are tested in one SIMD operation,
// with triangles pre-gathered into SoA blocks of 8.
#include <cstdint>
#include <span>
#include <string_view>
#include <optional>
#include <vector>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/kernels/isa.h"
#include "simdbvh/kernels/soa.h"

namespace simdbvh {

enum class Collapse : std::uint8_t {
    sah,     // Ylitie et al. 2017 section 4 dynamic program (default)
    greedy,  // adopt the child with the largest surface area until 8 children
};
std::string_view name(Collapse c);
std::optional<Collapse> parse_collapse(std::string_view s);

struct Bvh8Options {
    Collapse collapse = Collapse::sah;
    int max_leaf_size = 8;  // triangles per BVH8 leaf (one or more Tri8 blocks)
    // Collapse cost model (Ylitie 2017 section 4 adapted to Tri8 blocks): a
    // Node8 visit (one 8-wide box test) costs node_cost, a leaf costs
    // block_cost per Tri8 block, i.e. block_cost * ceil(n / 8) for n triangles.
    float node_cost = 1.0f;
    float block_cost = 1.0f;
};

// Child reference: inner node index, or a leaf (first Tri8 block, block count).
struct Child8 {
    std::uint32_t index = 0;  // inner: node index; leaf: first block
    std::uint32_t count = 0;  // 0 = inner node; leaf: number of Tri8 blocks; empty slot: kInvalidPrim
};

struct alignas(64) Node8 {
    Box8 boxes;         // 192 bytes: SoA lower/upper x, y, z; empty slots +inf/-inf, at the end
    Child8 children[8]; // 64 bytes
};
static_assert(sizeof(Node8) == 256 && alignof(Node8) == 64);

struct Bvh8Stats {
    double build_ms = 0;  // collapse + pack (add the BVH2's build_ms for the total)
    std::size_t nodes = 0, leaves = 0, blocks = 0, triangles = 0;
    int depth = 0;
    double sah_cost = 0;           // sum of cost * A(n)/A(root) (as the BVH2), node_cost / block_cost model
    double bytes_per_triangle = 0; // nodes + triangle blocks
    double fill_rate = 0;          // used child slots / (8 * nodes)
    double block_fill = 0;         // triangles / (8 * blocks)
};

class Bvh8 {
public:
    Bvh8() = default;
    static Bvh8 build(const Bvh2& bvh2, const Bvh8Options& opts = {});
    static Bvh8 build(const Mesh& mesh, const BuildOptions& bvh2_opts = {}, const Bvh8Options& opts = {});

    const std::vector<Node8>& nodes() const { return nodes_; }
    const std::vector<Tri8>& blocks() const { return blocks_; }
    const Bvh8Stats& stats() const { return stats_; }
    Aabb bounds() const { return bounds_; }

private:
    friend struct Bvh8Access;
    std::vector<Node8> nodes_;  // root at 0 (when the mesh is not empty)
    std::vector<Tri8> blocks_;
    Bvh8Stats stats_;
    Aabb bounds_;
};

// Closest hit and any hit, bit-identical to the BVH2 (same kernels, same tie
// rule). One switch on `isa` per batch; an unsupported isa throws simdbvh::Error.
// TraceOptions::stats: nodes_visited counts Node8s; box_tests and
// triangle_tests count SIMD lanes (8 per Node8 test, 8 per Tri8 block).
void intersect(const Bvh8& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& opts = {},
               Isa isa = active_isa());
void occluded(const Bvh8& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& opts = {},
              Isa isa = active_isa());
Hit intersect(const Bvh8& bvh, const Ray& ray, const TraceOptions& opts = {}, Isa isa = active_isa());
Hit occluded(const Bvh8& bvh, const Ray& ray, const TraceOptions& opts = {}, Isa isa = active_isa());

}  // namespace simdbvh
