// Scene build: one bottom level per geometry (a wide BVH for meshes, a BVH2
// over padded bounds for sphere and box sets), the instance records and world
// boxes, and the top-level BVH2 over the instance boxes.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>

#include "simdbvh/kernels/error.h"
#include "simdbvh/scene_accel/scene.h"

namespace simdbvh {

namespace {

std::vector<Aabb> root_children(const Bvh2Topology& t) {
    if (t.nodes.empty()) return {};
    const Node2& r = t.nodes[0];
    if (r.is_leaf()) return {r.box};
    return {t.nodes[r.first].box, t.nodes[r.first + 1].box};
}

template <int N>
std::vector<Aabb> root_children(const BvhN<N>& b) {
    std::vector<Aabb> out;
    if (b.nodes().empty()) return out;
    const auto& root = b.nodes()[0];
    for (int i = 0; i < N; ++i)
        if (!root.children[i].is_empty()) out.push_back(root.boxes.get(i));
    return out;
}

// A BVH2 over padded primitive bounds, the primitives gathered in leaf order.
template <class Prim, class BoundsFn>
Bvh2Topology build_shapes(const std::vector<Prim>& prims, std::vector<Prim>& gathered, BoundsFn bounds,
                          const BuildOptions& opts) {
    std::vector<Aabb> boxes(prims.size());
    std::vector<Vec3> centroids(prims.size());
    for (std::size_t i = 0; i < prims.size(); ++i) {
        boxes[i] = bounds(prims[i]);
        centroids[i] = boxes[i].center();
    }
    Bvh2Topology t = build_topology(boxes, centroids, opts);
    gathered.resize(t.prim_ids.size());
    for (std::size_t i = 0; i < t.prim_ids.size(); ++i) gathered[i] = prims[t.prim_ids[i]];
    return t;
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
        b.root_children = root_children(bvh);
        *bytes += bvh.nodes().size() * sizeof(typename BvhN<N>::Node) + bvh.blocks().size() * sizeof(Tri8);
        *prims += m->triangles.size();
        b.tree = std::move(bvh);
        return b;
    }
    Bvh2Topology t;
    if (const SphereSet* s = std::get_if<SphereSet>(&g)) {
        t = build_shapes(s->spheres, b.spheres, sphere_bounds, o.bottom);
        *bytes += b.spheres.size() * sizeof(Sphere);
        *prims += s->spheres.size();
    } else {
        const BoxSet& bs = std::get<BoxSet>(g);
        t = build_shapes(bs.boxes, b.boxes, padded_box, o.bottom);
        *bytes += b.boxes.size() * sizeof(Aabb);
        *prims += bs.boxes.size();
    }
    *bytes += topo_bytes(t);
    b.bounds = t.nodes.empty() ? Aabb{} : t.nodes[0].box;
    b.root_children = root_children(t);
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
    s.leaf_of_.assign(ni, kInvalidPrim);
    for (std::size_t j = 0; j < s.top_.nodes.size(); ++j) {
        const Node2& nd = s.top_.nodes[j];
        if (nd.is_leaf())
            for (std::uint32_t k = nd.first; k < nd.first + nd.count; ++k) s.leaf_of_[s.top_.prim_ids[k]] = std::uint32_t(j);
    }
    s.planes_ = scene.planes;
    s.slack_scale_ = static_cast<float>(0x1p-16 * max_cond);
    s.magnitude_ = magnitude;

    const std::size_t top_bytes = topo_bytes(s.top_);
    st.bytes += top_bytes + ni * (sizeof(InstanceRecord) + sizeof(std::uint32_t)) + s.planes_.size() * sizeof(Plane);
    st.bytes_per_instance = sizeof(InstanceRecord) + sizeof(std::uint32_t) + (ni ? (top_bytes + ni - 1) / ni : 0);
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
