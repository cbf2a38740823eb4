// Embree single-level instancing of a scene description (embree_instances.h).
#include "simdbvh/reference/embree_instances.h"
#include "embree_ray.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <string>
#include <vector>

#include "simdbvh/reference/embree.h"
#include "simdbvh/kernels/error.h"

namespace simdbvh::reference {

namespace {
// Per chunk of rays: which ones Embree may see (check_embree_ray), and the
// plane pass's buffers.
struct PlaneScratch {
    std::vector<std::uint8_t> ok;
    std::vector<Ray> clamped;
    std::vector<int> plane;
    std::vector<float> t;
};
// Rays per plane pass: the chunk our batches trace (scene/src/traverse.cpp).
constexpr std::size_t kPlaneChunk = 2048;
}  // namespace

struct EmbreeInstanceScene::Impl {
    RTCDevice device = nullptr;
    RTCScene top = nullptr;
    std::vector<RTCScene> children;
    std::vector<std::uint32_t> geometry_of;   // per instance
    std::vector<std::uint32_t> prim_divisor;  // per geometry: 6 for box sets (six quads per box), else 1
    std::vector<Plane> planes;
    std::uint32_t num_instances = 0;
    std::atomic<std::int64_t> mem{0};
    double build_ms = 0;
    void check(const char* what) const {
        const RTCError e = rtcGetDeviceError(device);
        if (e != RTC_ERROR_NONE)
            throw Error(std::string("Embree: ") + what + " failed (error " + std::to_string(int(e)) + ")");
    }
    static bool on_memory(void* user, ssize_t bytes, bool /*post*/) {
        static_cast<Impl*>(user)->mem.fetch_add(bytes, std::memory_order_relaxed);
        return true;
    }
    template <typename T>
    T* buffer(RTCGeometry g, RTCBufferType type, RTCFormat format, std::size_t count) {
        auto* p = static_cast<T*>(rtcSetNewGeometryBuffer(g, type, 0, format, sizeof(T), count));
        check("rtcSetNewGeometryBuffer");
        if (!p) throw Error("Embree: rtcSetNewGeometryBuffer returned null");
        return p;
    }
    RTCGeometry mesh_geometry(const Mesh& m) {
        RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
        struct V {
            float x, y, z;
        };
        struct I {
            std::uint32_t a, b, c;
        };
        V* v = buffer<V>(g, RTC_BUFFER_TYPE_VERTEX, RTC_FORMAT_FLOAT3, m.positions.size());
        I* idx = buffer<I>(g, RTC_BUFFER_TYPE_INDEX, RTC_FORMAT_UINT3, m.triangles.size());
        for (std::size_t i = 0; i < m.positions.size(); ++i)
            v[i] = {m.positions[i].x, m.positions[i].y, m.positions[i].z};
        for (std::size_t i = 0; i < m.triangles.size(); ++i)
            idx[i] = {m.triangles[i][0], m.triangles[i][1], m.triangles[i][2]};
        return g;
    }
    RTCGeometry sphere_geometry(const SphereSet& set) {
        RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
        struct V {
            float x, y, z, r;
        };
        V* v = buffer<V>(g, RTC_BUFFER_TYPE_VERTEX, RTC_FORMAT_FLOAT4, set.spheres.size());
        for (std::size_t i = 0; i < set.spheres.size(); ++i) {
            const Sphere& s = set.spheres[i];
            v[i] = {s.center.x, s.center.y, s.center.z, s.radius};
        }
        return g;
    }
    // Six quads per box, each a face of the box (8 shared corners per box).
    RTCGeometry box_geometry(const BoxSet& set) {
        RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_QUAD);
        struct V {
            float x, y, z;
        };
        struct Q {
            std::uint32_t a, b, c, d;
        };
        V* v = buffer<V>(g, RTC_BUFFER_TYPE_VERTEX, RTC_FORMAT_FLOAT3, 8 * set.boxes.size());
        Q* q = buffer<Q>(g, RTC_BUFFER_TYPE_INDEX, RTC_FORMAT_UINT4, 6 * set.boxes.size());
        static constexpr Q kFaces[6] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1},
                                        {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
        for (std::size_t i = 0; i < set.boxes.size(); ++i) {
            const Aabb& b = set.boxes[i];
            for (std::uint32_t c = 0; c < 8; ++c)  // corner c: bit 0 x, bit 1 y, bit 2 z
                v[8 * i + c] = {(c & 1) ? b.hi.x : b.lo.x, (c & 2) ? b.hi.y : b.lo.y, (c & 4) ? b.hi.z : b.lo.z};
            const auto base = std::uint32_t(8 * i);
            for (int f = 0; f < 6; ++f)
                q[6 * i + f] = {base + kFaces[f].a, base + kFaces[f].b, base + kFaces[f].c, base + kFaces[f].d};
        }
        return g;
    }
    // Planes, as ours (scene/src/traverse.cpp): one batched pass of
    // shapes.h's nearest_planes over the rays Embree takes (w.ok),
    // each clamped to its hit so far (in the caller's parameter, which
    // prepare_scaled rescales with the ray); a plane replaces a hit only when
    // strictly nearer (planes lose ties to instances and to lower planes).
    // any: the first plane hit, as our any-hit query takes it.
    void planes_before(std::span<const Ray> rays, std::span<SceneHit> hits, bool any, PlaneScratch& w) const {
        if (planes.empty()) return;
        // Rays without a hit yet (all of them when the planes go first, as
        // for any hit) are taken as given, without the copy (as ours,
        // scene/src/traverse.cpp).
        std::span<const Ray> clamped = rays;
        if (std::any_of(hits.begin(), hits.begin() + std::ptrdiff_t(rays.size()),
                        [](const SceneHit& h) { return h.hit(); })) {
            w.clamped.assign(rays.begin(), rays.end());
            for (std::size_t i = 0; i < rays.size(); ++i)
                if (hits[i].hit()) w.clamped[i].tmax = hits[i].t;
            clamped = w.clamped;
        }
        w.plane.resize(rays.size());
        w.t.resize(rays.size());
        nearest_planes(clamped, planes, any, w.plane, w.t);
        for (std::size_t i = 0; i < rays.size(); ++i) {
            const int k = w.plane[i];
            if (k < 0 || !w.ok[i] || (hits[i].hit() && !(w.t[i] < hits[i].t))) continue;
            hits[i] = SceneHit{w.t[i], 0.0f, 0.0f, std::uint32_t(k), kNoGeometry, num_instances + std::uint32_t(k)};
        }
    }
    ~Impl() {
        if (top) rtcReleaseScene(top);
        for (RTCScene s : children)
            if (s) rtcReleaseScene(s);
        if (device) rtcReleaseDevice(device);
    }
};

EmbreeInstanceScene::EmbreeInstanceScene(const SceneDesc& scene) : impl_(std::make_unique<Impl>()) {
    validate(scene);
    Impl& s = *impl_;
    s.device = rtcNewDevice("");
    if (!s.device) throw Error("Embree: rtcNewDevice failed");
    rtcSetDeviceMemoryMonitorFunction(s.device, &Impl::on_memory, &s);
    s.planes = scene.planes;
    s.num_instances = std::uint32_t(scene.instances.size());
    const auto t0 = std::chrono::steady_clock::now();
    for (const Geometry& geometry : scene.geometries) {
        RTCScene child = rtcNewScene(s.device);
        s.children.push_back(child);
        RTCGeometry g = nullptr;
        if (const auto* m = std::get_if<Mesh>(&geometry)) g = s.mesh_geometry(*m);
        else if (const auto* sp = std::get_if<SphereSet>(&geometry)) g = s.sphere_geometry(*sp);
        else g = s.box_geometry(std::get<BoxSet>(geometry));
        s.prim_divisor.push_back(std::holds_alternative<BoxSet>(geometry) ? 6 : 1);
        rtcCommitGeometry(g);
        rtcAttachGeometryByID(child, g, 0);
        rtcReleaseGeometry(g);
        rtcCommitScene(child);
        s.check("rtcCommitScene (geometry)");
    }
    s.top = rtcNewScene(s.device);
    for (std::size_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& in = scene.instances[i];
        RTCGeometry inst = rtcNewGeometry(s.device, RTC_GEOMETRY_TYPE_INSTANCE);
        rtcSetGeometryInstancedScene(inst, s.children[in.geometry]);
        float m[12];
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 4; ++c) m[4 * r + c] = in.transform.m[r][c];
        rtcSetGeometryTransform(inst, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, m);
        rtcCommitGeometry(inst);
        rtcAttachGeometryByID(s.top, inst, unsigned(i));
        rtcReleaseGeometry(inst);
        s.geometry_of.push_back(in.geometry);
    }
    rtcCommitScene(s.top);
    s.check("rtcCommitScene (instances)");
    s.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

EmbreeInstanceScene::~EmbreeInstanceScene() = default;

double EmbreeInstanceScene::build_ms() const { return impl_->build_ms; }

std::size_t EmbreeInstanceScene::bytes() const {
    const std::int64_t m = impl_->mem.load();
    return m > 0 ? std::size_t(m) : 0;
}

namespace {

// The loop both queries share, a chunk of rays at a time (as our batches):
// each ray's answer starts as a miss, and w.ok marks the rays Embree may see
// (the others stay misses).
template <class Fn>
void for_each_chunk(std::span<const Ray> rays, std::span<SceneHit> hits, PlaneScratch& w, Fn&& fn) {
    simdbvh::detail::check_size(hits.size(), rays.size(), "hits");
    for (std::size_t b = 0; b < rays.size(); b += kPlaneChunk) {
        const std::size_t n = std::min(kPlaneChunk, rays.size() - b);
        w.ok.resize(n);
        for (std::size_t i = 0; i < n; ++i) {
            hits[b + i] = SceneHit{};
            w.ok[i] = check_embree_ray(rays[b + i]) == EmbreeRayCheck::ok;
        }
        fn(rays.subspan(b, n), hits.subspan(b, n));
    }
}

}  // namespace

void EmbreeInstanceScene::intersect(std::span<const Ray> rays, std::span<SceneHit> hits) const {
    const Impl& s = *impl_;
    PlaneScratch w;
    for_each_chunk(rays, hits, w, [&](std::span<const Ray> chunk, std::span<SceneHit> out) {
        for (std::size_t i = 0; i < chunk.size(); ++i) {
            if (!w.ok[i]) continue;
            alignas(16) RTCRayHit rh = embree_ray_hit(chunk[i]);
            RTCIntersectContext ctx;
            rtcInitIntersectContext(&ctx);
            rtcIntersect1(s.top, &ctx, &rh);
            if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
                const std::uint32_t inst = rh.hit.instID[0], geom = s.geometry_of[inst];
                out[i] = SceneHit{rh.ray.tfar, rh.hit.u, rh.hit.v, rh.hit.primID / s.prim_divisor[geom], geom, inst};
            }
        }
        s.planes_before(chunk, out, false, w);
    });
}

void EmbreeInstanceScene::occluded(std::span<const Ray> rays, std::span<SceneHit> hits) const {
    const Impl& s = *impl_;
    PlaneScratch w;
    for_each_chunk(rays, hits, w, [&](std::span<const Ray> chunk, std::span<SceneHit> out) {
        s.planes_before(chunk, out, true, w);  // planes first, as ours
        for (std::size_t i = 0; i < chunk.size(); ++i) {
            if (out[i].hit() || !w.ok[i]) continue;
            alignas(16) RTCRay ray = embree_ray_hit(chunk[i]).ray;
            RTCIntersectContext ctx;
            rtcInitIntersectContext(&ctx);
            rtcOccluded1(s.top, &ctx, &ray);
            if (ray.tfar < 0.0f) out[i] = SceneHit{0.0f, 0.0f, 0.0f, 0, kNoGeometry, kInvalidPrim};
        }
    });
}

}  // namespace simdbvh::reference
