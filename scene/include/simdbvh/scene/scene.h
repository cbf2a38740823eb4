#pragma once
// Scenes: several geometries (triangle meshes, sphere sets, box sets), each
// with its own bottom-level hierarchy, placed any number of times by instances
// (a geometry and a 3x4 affine transform), plus planes kept outside every
// hierarchy and tested per ray (seed 004). A top-level BVH2 bounds the
// instances; rays enter an instance through its inverse transform.
//
// Results are bit-identical to brute_force_intersect(SceneDesc, ...) (every
// instance, every primitive, every plane, through the same object_ray()
// arithmetic) at every width, ISA and instance-bounds method. Closest hit:
// smaller t, then lower instance id, then lower primitive id (scene_hit.h);
// planes have instance ids after the instances.
//
// The top-level box test widens every box by a per-ray slack of 2^-16 *
// max cond(A) * (max |origin component| + the scene's largest coordinate): the
// object-space ray is rounded, and a hit it finds lies within that distance of
// the world ray (bounded by cond(A) float roundings of |o| + |t d|).
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <variant>
#include <vector>

#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/scene/scene_hit.h"
#include "simdbvh/scene/shapes.h"
#include "simdbvh/scene/transform.h"

namespace simdbvh {

struct SphereSet {
    std::vector<Sphere> spheres;
};
struct BoxSet {
    std::vector<Aabb> boxes;
};
using Geometry = std::variant<Mesh, SphereSet, BoxSet>;

struct Instance {
    std::uint32_t geometry = 0;  // index into SceneDesc::geometries
    Affine3 transform;           // object -> world
};

// What a scene is made of (the input of a build and of the brute force).
struct SceneDesc {
    std::vector<Geometry> geometries;
    std::vector<Instance> instances;
    std::vector<Plane> planes;
};

// Throws simdbvh::Error naming the offending item (e.g. "instances[3].transform:
// singular") for a missing geometry reference, a non-finite value, a negative
// radius, an inverted box, a zero plane normal, a singular transform, a
// sphere, box or instance whose bounds exceed the float range (e.g. a radius
// of 3e38, or a transform scaling a geometry past it), or a mesh the BVH2 rejects.
void validate(const SceneDesc& scene);

// Instance bounds: seed 004's 8 transformed corners of the bottom tree's box,
// or the union of the transformed corners of the bottom tree's root child
// boxes (tighter for rotated objects).
enum class InstanceBounds : std::uint8_t { corners, child_corners };

struct SceneOptions {
    InstanceBounds bounds = InstanceBounds::child_corners;
    BuildOptions bottom;  // bottom-level BVH2 builds (meshes, spheres, boxes), before the wide collapse
    WideOptions wide;     // bottom-level wide collapse (meshes; sphere and box sets: leaves of at most 4)
    BuildOptions top;     // top-level BVH2 over the instance boxes (max_leaf_size is set to 1: one instance per leaf)
};

struct SceneStats {
    double build_ms = 0;
    std::size_t geometries = 0, instances = 0, planes = 0;
    std::size_t primitives = 0;            // over the geometries (each counted once)
    std::size_t instanced_primitives = 0;  // over the instances (what a flattened scene holds)
    // Sums of the instance world-box volumes by each method (both computed at every build).
    double volume_corners = 0, volume_child_corners = 0;
    std::size_t bytes = 0;               // bottom trees + top tree + instance records + planes
    std::size_t bytes_per_instance = 0;  // instance record + its share of the top trees (its world box lives there)
    double max_cond = 1.0;
};

// The wide hierarchy of a sphere or box set: a BVH2 over the padded
// primitive bounds (shapes.h), collapsed to N children per node as a mesh's
// is, whose leaves are ranges of the primitives gathered in leaf order
// (ChildN::leaf(first, count): `count` primitives from BottomLevel::spheres
// or ::boxes[first]). Its nodes take the same SIMD node test as a mesh's.
template <int N>
struct ShapeTree {
    std::vector<NodeN<N>> nodes;          // root at 0 (none for an empty set)
    std::vector<std::uint32_t> prim_ids;  // gathered position -> primitive id
};

// Bottom level of one geometry. Meshes: a wide BVH; spheres and boxes: a
// ShapeTree, the primitives in its leaf order.
template <int N>
struct BottomLevel {
    std::variant<BvhN<N>, ShapeTree<N>> tree;
    std::vector<Sphere> spheres;      // spheres[i]: primitive prim_ids[i] (sphere sets)
    std::vector<Aabb> boxes;          // boxes[i]: primitive prim_ids[i] (box sets)
    Aabb bounds;                      // root box
    std::vector<Aabb> root_children;  // the root's child boxes
};

struct InstanceRecord {  // what a trace reads per instance visit (52 bytes)
    Affine3 inv;         // world -> object
    std::uint32_t geometry;
};
static_assert(sizeof(InstanceRecord) == 52);

// The top level collapsed to 8 children per node (the SAH collapse of the wide
// trees, over the top BVH2), walked by batches (kernels::collect_box8_tree);
// with up to kernels::kCollectBoxesMax leaves, batches test the rays against
// the leaf boxes instead (kernels::collect_boxes: the unions of 8 leaf boxes,
// then the boxes of the unions a ray hits).
// Lane j of wide node n: children[8 n + j] is kernels::kBoxTreeEmpty (unused),
// a wide node m > n, or kernels::kBoxTreeLeaf | k for the top BVH2's leaf node
// k (its box and its instances, top_instance(first, 0 .. count - 1)). An
// inner lane's box is the union of its node's lanes (computed per batch, with
// the rays' slack). 32 bytes per wide node.
struct TopWide {
    std::vector<std::uint32_t> children;  // 8 per wide node
};

template <int N>
class SceneBvhN {
    static_assert(kValidWidth<N>, "widths: 4, 8, 16");

public:
    SceneBvhN() = default;
    // Validates (throws simdbvh::Error) and builds every bottom level and the top level.
    static SceneBvhN build(const SceneDesc& scene, const SceneOptions& opts = {});

    const std::vector<BottomLevel<N>>& bottoms() const { return bottoms_; }
    const std::vector<InstanceRecord>& instances() const { return instances_; }
    // The top BVH2 over the instance boxes. Its leaves hold one instance each,
    // whose id is the leaf's `first`, and prim_ids is empty (4 bytes per
    // instance saved), unless the depth cap forced a larger leaf: then leaf
    // ids are prim_ids[first, first + count). top_instance() reads either.
    const Bvh2Topology& top() const { return top_; }
    std::uint32_t top_instance(std::uint32_t first, std::uint32_t k) const {
        return top_.prim_ids.empty() ? first : top_.prim_ids[first + k];
    }
    const TopWide& top_wide() const { return top_wide_; }
    const std::vector<Plane>& planes() const { return planes_; }
    const SceneStats& stats() const { return stats_; }
    float slack_scale() const { return slack_scale_; }  // 2^-16 * max cond
    float scene_magnitude() const { return magnitude_; }

private:
    std::vector<BottomLevel<N>> bottoms_;
    std::vector<InstanceRecord> instances_;
    Bvh2Topology top_;
    TopWide top_wide_;
    std::vector<Plane> planes_;
    SceneStats stats_;
    float slack_scale_ = 0.0f;
    float magnitude_ = 0.0f;
};
extern template class SceneBvhN<4>;
extern template class SceneBvhN<8>;
extern template class SceneBvhN<16>;

// How a scene is traced: the options struct of every scene query.
struct SceneTraceOptions {
    // The code path of the wide traversals (bottom levels, shapes, planes): an
    // unsupported one throws simdbvh::Error. Unset: active_isa().
    std::optional<Isa> isa;
    int threads = 1;  // batched calls: split the rays over this many threads
};

// Closest hit and any hit. Any hit: some hit in [tmin, tmax] (a real one,
// with its ids), or SceneHit{}. Hits do not depend on the options.
template <int N>
SceneHit intersect(const SceneBvhN<N>& scene, const Ray& ray, const SceneTraceOptions& opts = {});
template <int N>
SceneHit occluded(const SceneBvhN<N>& scene, const Ray& ray, const SceneTraceOptions& opts = {});
template <int N>
void intersect(const SceneBvhN<N>& scene, std::span<const Ray> rays, std::span<SceneHit> hits,
               const SceneTraceOptions& opts = {});
template <int N>
void occluded(const SceneBvhN<N>& scene, std::span<const Ray> rays, std::span<SceneHit> hits,
              const SceneTraceOptions& opts = {});
// A batch is traced in wavefront chunks of at most this many rays (fewer when
// the threads split a smaller batch, at least 2,048): a caller feeding a large
// batch in pieces loses nothing with pieces of this size (smaller pieces give
// smaller chunks, and fewer rays per bottom-level call).
inline constexpr std::size_t kSceneChunkRays = 32768;

// The reference: every instance (through object_ray with the same inverse),
// every primitive, every plane; no hierarchy. Validates first (throws).
void brute_force_intersect(const SceneDesc& scene, std::span<const Ray> rays, std::span<SceneHit> hits);
// Any hit of the brute force: the planes' first hit, else the first hit in
// instance then primitive order.
void brute_force_occluded(const SceneDesc& scene, std::span<const Ray> rays, std::span<SceneHit> hits);

double volume(const Aabb& b);  // in double; 0 for an empty box

// The world-space geometric normal at a hit of `world` (not normalised; zero
// for a miss): triangle cross(v1 - v0, v2 - v0), sphere p - c, box the hit
// face's axis (the face nearest the hit point), plane its normal; object-space
// normals go to world space through the inverse transpose of the instance's A.
Vec3 hit_normal(const SceneDesc& scene, const Ray& world, const SceneHit& hit);
// The union of the instances' world boxes (corners method); planes are unbounded and not included.
Aabb world_bounds(const SceneDesc& scene);

}  // namespace simdbvh
