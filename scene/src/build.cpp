// Scene build: one bottom level per geometry (a wide BVH for meshes, a wide
// ShapeTree for sphere and box sets), the instance records and world boxes,
// and the top-level BVH2 over the instance boxes.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <string>

#include "simdbvh/kernels/batch.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/scene/scene.h"
#include "simdbvh/bvh8/internal/collapse.h"  // bvh8/src

namespace simdbvh {

namespace {

template <class Nodes>  // a BvhN's NodesN or a scene's top-level std::vector of NodeN
std::vector<Aabb> root_children(const Nodes& nodes) {
    std::vector<Aabb> out;
    if (nodes.empty()) return out;
    for (int i = 0; i < Nodes::value_type::kWidth; ++i)
        if (!nodes[0].children[i].is_empty()) out.push_back(nodes[0].boxes.get(i));
    return out;
}

// Shape leaves of at most this many primitives: the collapse's cost model
// (bvh8/internal/simdbvh/bvh8/internal/collapse.h) prices a leaf by Tri8 blocks of 8, but a shape leaf
// tests its primitives one at a time in double.
inline constexpr int kShapeLeafMax = 4;

// A ShapeTree over padded primitive bounds: a BVH2, collapsed to N wide and
// packed, the primitives gathered in the wide tree's leaf order.
template <int N, class Prim, class BoundsFn>
ShapeTree<N> build_shapes(const std::vector<Prim>& prims, std::vector<Prim>& gathered, BoundsFn bounds,
                          const SceneOptions& o) {
    std::vector<Aabb> boxes(prims.size());
    std::vector<Vec3> centroids(prims.size());
    for (std::size_t i = 0; i < prims.size(); ++i) {
        boxes[i] = bounds(prims[i]);
        centroids[i] = boxes[i].center();
    }
    BuildOptions bo = o.bottom;
    bo.max_leaf_size = std::min(bo.max_leaf_size, kShapeLeafMax);
    const Bvh2Topology t = build_topology(boxes, centroids, bo);
    ShapeTree<N> w;
    if (t.nodes.empty()) return w;
    WideOptions wo = o.wide;
    wo.max_leaf_size = kShapeLeafMax;
    wo.threads = 1;
    const bvh8::WideTopology<N> topo = bvh8::collapse<N>(std::span<const Node2>(t.nodes), t.prim_ids.size(), wo);
    gathered.resize(topo.prims);  // in the leaf order, which the wide leaves index
    w.prim_ids.assign(t.prim_ids.begin(), t.prim_ids.end());
    for (std::size_t k = 0; k < topo.prims; ++k) gathered[k] = prims[t.prim_ids[k]];
    using Child = ChildN<N>;
    w.nodes.resize(topo.nodes.size());
    for (std::size_t j = 0; j < topo.nodes.size(); ++j) {
        NodeN<N>& n = w.nodes[j];
        n.boxes.clear();
        for (int i = 0; i < N; ++i) n.children[i] = Child::empty();
        const bvh8::WideNode<N>& wn = topo.nodes[j];
        for (int i = 0; i < wn.child_count; ++i) {
            const bvh8::WideChild& c = wn.children[std::size_t(i)];
            if (c.is_leaf() && c.count > Child::kMaxBlocks)
                throw Error("shape set: a leaf of " + std::to_string(c.count) + " primitives (at most " +
                            std::to_string(Child::kMaxBlocks) + " at width " + std::to_string(N) +
                            "; too many primitives share one position)");
            n.boxes.set(i, c.box);
            n.children[i] = c.is_leaf() ? Child::leaf(c.index, c.count) : Child::inner(c.index);
        }
    }
    return w;
}

template <int N>
std::size_t tree_bytes(const ShapeTree<N>& t) {
    return t.nodes.size() * sizeof(NodeN<N>) + t.prim_ids.size() * sizeof(std::uint32_t);
}

std::size_t topo_bytes(const Bvh2Topology& t) {
    return t.nodes.size() * sizeof(Node2) + t.prim_ids.size() * sizeof(std::uint32_t);
}

template <int N>
BottomLevel<N> build_bottom(const Geometry& g, const SceneOptions& o, std::size_t* bytes, std::size_t* prims) {
    BottomLevel<N> b;
    if (const Mesh* m = std::get_if<Mesh>(&g)) {
        BvhN<N> bvh = BvhN<N>::build(*m, o.bottom, o.wide);
        b.bounds = bvh.bounds();
        b.root_children = root_children(bvh.nodes());
        *bytes += bvh.nodes().size() * sizeof(typename BvhN<N>::Node) + bvh.blocks().size() * sizeof(Tri8);
        *prims += m->triangles.size();
        b.tree = std::move(bvh);
        return b;
    }
    ShapeTree<N> t;
    if (const SphereSet* s = std::get_if<SphereSet>(&g)) {
        t = build_shapes<N>(s->spheres, b.spheres, sphere_bounds, o);
        *bytes += b.spheres.size() * sizeof(Sphere);
        *prims += s->spheres.size();
    } else {
        const BoxSet& bs = std::get<BoxSet>(g);
        t = build_shapes<N>(bs.boxes, b.boxes, padded_box, o);
        *bytes += b.boxes.size() * sizeof(Aabb);
        *prims += bs.boxes.size();
    }
    *bytes += tree_bytes(t);
    b.root_children = root_children(t.nodes);
    for (const Aabb& c : b.root_children) b.bounds.grow(c);
    b.tree = std::move(t);
    return b;
}

Aabb union_of_transformed(const Affine3& t, const std::vector<Aabb>& boxes) {
    Aabb out;
    for (const Aabb& b : boxes) out.grow(transform_box(t, b));
    return out;
}

float max_abs(const Aabb& b) {
    float m = 0.0f;
    for (int a = 0; a < 3; ++a) m = std::max({m, std::fabs(b.lo[a]), std::fabs(b.hi[a])});
    return m;
}

// The top BVH2 collapsed to 8 children per node (TopWide in scene.h): the
// collapse of the wide trees with one BVH2 leaf per wide leaf.
TopWide wide_top(const Bvh2Topology& top) {
    TopWide w;
    if (top.nodes.empty()) return w;
    WideOptions o;
    o.max_leaf_size = 1;  // a BVH2 leaf (one instance, or more with equal boxes) is one lane
    o.threads = 1;
    const bvh8::WideTopology<8> t = bvh8::collapse<8>(std::span<const Node2>(top.nodes), top.prim_ids.size(), o);
    // A BVH2 leaf's position range in prim_ids -> its node (every wide leaf is one BVH2 leaf).
    std::vector<std::uint32_t> leaf_at(top.prim_ids.size(), kInvalidPrim);
    for (std::size_t j = 0; j < top.nodes.size(); ++j)
        if (top.nodes[j].is_leaf() && top.nodes[j].count > 0) leaf_at[top.nodes[j].first] = std::uint32_t(j);
    w.children.assign(8 * t.nodes.size(), kernels::kBoxTreeEmpty);
    for (std::size_t n = 0; n < t.nodes.size(); ++n) {
        const bvh8::WideNode<8>& wn = t.nodes[n];
        for (int c = 0; c < wn.child_count; ++c) {
            const bvh8::WideChild& ch = wn.children[std::size_t(c)];
            std::uint32_t code;
            if (ch.is_leaf()) {
                const std::uint32_t leaf = leaf_at[ch.index];
                if (leaf == kInvalidPrim || top.nodes[leaf].count != ch.count)
                    throw Error("scene: the top level's wide collapse split a BVH2 leaf");
                code = kernels::kBoxTreeLeaf | leaf;
            } else {
                code = ch.index;
            }
            w.children[8 * n + std::size_t(c)] = code;
        }
    }
    return w;
}

// Every leaf of one instance (all of them, unless the depth cap forced a
// larger leaf): each leaf's `first` becomes its instance id and the leaf-order
// id array (4 bytes per instance) is dropped. Otherwise the ids stay as built.
void fold_instance_ids(Bvh2Topology& top) {
    for (const Node2& n : top.nodes)
        if (n.is_leaf() && n.count != 1) return;
    for (Node2& n : top.nodes)
        if (n.is_leaf()) n.first = top.prim_ids[n.first];
    std::vector<std::uint32_t>().swap(top.prim_ids);
}

}  // namespace

template <int N>
SceneBvhN<N> SceneBvhN<N>::build(const SceneDesc& scene, const SceneOptions& opts) {
    const auto t0 = std::chrono::steady_clock::now();
    validate(scene);
    SceneBvhN s;
    SceneStats& st = s.stats_;
    std::vector<std::size_t> geom_prims(scene.geometries.size(), 0);
    for (std::size_t g = 0; g < scene.geometries.size(); ++g)
        s.bottoms_.push_back(build_bottom<N>(scene.geometries[g], opts, &st.bytes, &geom_prims[g]));
    st.primitives = std::accumulate(geom_prims.begin(), geom_prims.end(), std::size_t{0});

    const std::size_t ni = scene.instances.size();
    s.instances_.resize(ni);
    std::vector<Aabb> boxes(ni);
    std::vector<Vec3> centroids(ni);
    double max_cond = 1.0;
    float magnitude = 0.0f;
    for (std::size_t i = 0; i < ni; ++i) {
        const Instance& in = scene.instances[i];
        const InverseAffine inv = invert(in.transform);
        s.instances_[i] = InstanceRecord{inv.inv, in.geometry};
        const BottomLevel<N>& b = s.bottoms_[in.geometry];
        const Aabb corners = transform_box(in.transform, b.bounds);
        const Aabb tight = b.root_children.empty() ? corners : union_of_transformed(in.transform, b.root_children);
        st.volume_corners += volume(corners);
        st.volume_child_corners += volume(tight);
        const Aabb box = opts.bounds == InstanceBounds::corners ? corners : tight;
        boxes[i] = box;
        centroids[i] = box.center();
        st.instanced_primitives += geom_prims[in.geometry];
        if (!box.is_empty()) {
            max_cond = std::max(max_cond, inv.cond);
            magnitude = std::max(magnitude, max_abs(box));
            for (int r = 0; r < 3; ++r) magnitude = std::max(magnitude, std::fabs(in.transform.m[r][3]));
        }
    }
    BuildOptions top = opts.top;
    top.max_leaf_size = 1;
    top.min_leaf_size = 1;
    s.top_ = build_topology(boxes, centroids, top);
    s.top_wide_ = wide_top(s.top_);
    fold_instance_ids(s.top_);
    s.planes_ = scene.planes;
    s.slack_scale_ = static_cast<float>(0x1p-16 * max_cond);
    s.magnitude_ = magnitude;

    const std::size_t top_bytes = topo_bytes(s.top_) + s.top_wide_.children.size() * sizeof(std::uint32_t);
    st.bytes += top_bytes + ni * sizeof(InstanceRecord) + s.planes_.size() * sizeof(Plane);
    st.bytes_per_instance = sizeof(InstanceRecord) + (ni ? (top_bytes + ni - 1) / ni : 0);
    st.geometries = scene.geometries.size();
    st.instances = ni;
    st.planes = scene.planes.size();
    st.max_cond = max_cond;
    st.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return s;
}

template class SceneBvhN<4>;
template class SceneBvhN<8>;
template class SceneBvhN<16>;

}  // namespace simdbvh
