#pragma once
// BVH2 builders. The builders see only primitive boxes and centroids; they
// know nothing about triangles.
#include <cstdint>
#include <span>
#include <string_view>
#include <optional>
#include <vector>

#include "simdbvh/kernels/error.h"  // simdbvh::Error, thrown by everything declared here
#include "simdbvh/bvh2/node.h"
#include "simdbvh/kernels/aabb.h"

namespace simdbvh {

enum class Builder : std::uint8_t {
    sah_binned,  // binned SAH (Wald 2007), the default
    sah_sweep,   // full sweep SAH over sorted centroids, the quality reference
    midpoint,    // seed 000: longest axis, centroid-bounds midpoint, leaf at <= 4
    median,      // seed 004: Shirley, axis cycles x, y, z with depth, split the sorted list in half
    variance,    // seed 002: axis of greatest centroid variance (Welford), split at the mean
};
std::string_view name(Builder b);
std::optional<Builder> parse_builder(std::string_view s);

struct BuildOptions {
    Builder builder = Builder::sah_binned;
    int bins = 16;          // binned SAH: 8, 16, 32 or 64
    int max_leaf_size = 8;  // SAH builders: leaves never hold more (unless the depth cap forces it)
    int min_leaf_size = 1;
    float traversal_cost = 1.0f;     // SAH: cost of one box test relative to ...
    float intersection_cost = 1.0f;  // ... one triangle test
    int max_depth = 64;              // hard cap; the traversal stack is sized from it
    int threads = 1;                 // build threads (one below 32,768 primitives); the same tree for any count
};
inline constexpr int kMaxDepth = 64;

// The tree: nodes (root at 0, children adjacent) and the leaf permutation.
struct Bvh2Topology {
    Nodes2 nodes;
    std::vector<std::uint32_t> prim_ids;
};

// Builds a BVH2 over primitives given by their boxes and centroids. Primitives
// with an empty box are left out of the tree (they can never be hit).
Bvh2Topology build_topology(std::span<const Aabb> boxes, std::span<const Vec3> centroids,
                            const BuildOptions& opts = {});

// The same over a mesh's triangles (box of the three vertices, centroid = box centre).
struct Mesh;
Bvh2Topology build_topology(const Mesh& mesh, const BuildOptions& opts = {});

// SAH cost of a topology: C = sum over inner nodes of Ct * A(n)/A(root) + sum over leaves of Ci * N * A(n)/A(root).
double sah_cost(const Bvh2Topology& topo, float traversal_cost = 1.0f, float intersection_cost = 1.0f);
// The same over nodes and the number of triangles in the leaves.
double sah_cost(std::span<const Node2> nodes, std::size_t prims, float traversal_cost = 1.0f,
                float intersection_cost = 1.0f);

}  // namespace simdbvh
