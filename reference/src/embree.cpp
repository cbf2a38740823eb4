// Embree 3 wrapper: see simdbvh/reference/embree.h.
#include "simdbvh/reference/embree.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
#include <thread>

#include "embree_ray.h"
#include "simdbvh/kernels/error.h"

namespace simdbvh::reference {
namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

const char* error_name(RTCError e) {
    switch (e) {
    case RTC_ERROR_NONE: return "RTC_ERROR_NONE";
    case RTC_ERROR_UNKNOWN: return "RTC_ERROR_UNKNOWN";
    case RTC_ERROR_INVALID_ARGUMENT: return "RTC_ERROR_INVALID_ARGUMENT";
    case RTC_ERROR_INVALID_OPERATION: return "RTC_ERROR_INVALID_OPERATION";
    case RTC_ERROR_OUT_OF_MEMORY: return "RTC_ERROR_OUT_OF_MEMORY";
    case RTC_ERROR_UNSUPPORTED_CPU: return "RTC_ERROR_UNSUPPORTED_CPU";
    case RTC_ERROR_CANCELLED: return "RTC_ERROR_CANCELLED";
    }
    return "RTC_ERROR_?";
}

// Embree's Ray::valid() bound on |org| and |dir| components (FLT_LARGE).
constexpr float kEmbreeLarge = 1.844E18f;

bool within_large(const Vec3& a) {
    return std::fabs(a.x) <= kEmbreeLarge && std::fabs(a.y) <= kEmbreeLarge && std::fabs(a.z) <= kEmbreeLarge;
}

}  // namespace

std::string_view name(EmbreeQuality q) {
    switch (q) {
    case EmbreeQuality::medium: return "medium";
    case EmbreeQuality::high: return "high";
    case EmbreeQuality::refit: return "refit";
    }
    return "?";
}

std::optional<EmbreeQuality> parse_embree_quality(std::string_view s) {
    for (EmbreeQuality q : {EmbreeQuality::medium, EmbreeQuality::high, EmbreeQuality::refit})
        if (s == name(q)) return q;
    return std::nullopt;
}

std::string method_name(const EmbreeOptions& o) {
    std::string s = "embree-" + std::string(name(o.quality));
    if (o.robust) s += "-robust";
    return s;
}

EmbreeRayCheck check_embree_ray(const Ray& r) {
    // valid_ray is prepare(r).valid without the rest of prepare() (its
    // divisions): this runs per ray inside every timed Embree row.
    if (!valid_ray(r)) return EmbreeRayCheck::invalid;
    // Embree asserts tnear >= 0 and |org|, |dir| <= FLT_LARGE (BVHNIntersector1).
    if (!(r.tmin >= 0.0f) || !within_large(r.org) || !within_large(r.dir)) return EmbreeRayCheck::unsupported;
    return EmbreeRayCheck::ok;
}

struct EmbreeScene::Impl {
    EmbreeOptions opts;
    EmbreeStats stats;
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;

    // Errors: Embree calls back from inside its C API, where throwing is not
    // allowed; record the first one and throw after the call returns.
    std::mutex error_mutex;
    std::atomic<bool> failed{false};
    std::string error;

    // Memory monitor (may be called from Embree's build threads).
    std::atomic<std::int64_t> mem_current{0};
    std::atomic<std::int64_t> mem_peak{0};
    std::atomic<bool> mem_seen{false};

    mutable std::atomic<std::uint64_t> invalid{0};
    mutable std::atomic<std::uint64_t> unsupported{0};

    ~Impl() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }

    static void on_error(void* user, RTCError code, const char* str) {
        auto* self = static_cast<Impl*>(user);
        std::lock_guard<std::mutex> lock(self->error_mutex);
        if (self->failed.load()) return;
        self->error = std::string("Embree: ") + error_name(code) + (str ? std::string(": ") + str : std::string());
        self->failed.store(true);
    }

    static bool on_memory(void* user, ssize_t bytes, bool /*post*/) {
        auto* self = static_cast<Impl*>(user);
        self->mem_seen.store(true, std::memory_order_relaxed);
        const std::int64_t now = self->mem_current.fetch_add(bytes) + bytes;
        std::int64_t peak = self->mem_peak.load();
        while (now > peak && !self->mem_peak.compare_exchange_weak(peak, now)) {}
        return true;  // never refuse an allocation
    }

    void check(const char* what) const {
        if (failed.load(std::memory_order_acquire)) {
            std::lock_guard<std::mutex> lock(const_cast<std::mutex&>(error_mutex));
            throw Error(std::string(what) + ": " + error);
        }
    }
};

EmbreeScene::EmbreeScene(const Mesh& mesh, const EmbreeOptions& opts) : impl_(std::make_unique<Impl>()) {
    validate(mesh);
    if (mesh.size() > kMaxTriangles - 1) throw Error("mesh has too many triangles for Embree");
    if (opts.threads < 0) throw Error("EmbreeOptions::threads must be >= 0");
    Impl& s = *impl_;
    s.opts = opts;
    s.stats.triangles = mesh.size();
    s.stats.vertices = mesh.positions.size();
    s.stats.threads =
        opts.threads > 0 ? opts.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));

    const auto t0 = Clock::now();
    const std::string config =
        "verbose=0" + (opts.threads > 0 ? ",threads=" + std::to_string(opts.threads) : std::string());
    s.device = rtcNewDevice(config.c_str());
    if (!s.device) {
        const RTCError e = rtcGetDeviceError(nullptr);
        throw Error(std::string("Embree: rtcNewDevice(\"") + config + "\") failed: " + error_name(e));
    }
    rtcSetDeviceErrorFunction(s.device, &Impl::on_error, &s);
    rtcSetDeviceMemoryMonitorFunction(s.device, &Impl::on_memory, &s);

    s.scene = rtcNewScene(s.device);
    s.check("rtcNewScene");
    const bool refit = opts.quality == EmbreeQuality::refit;
    rtcSetSceneFlags(s.scene,
                     RTCSceneFlags((opts.robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE) |
                                   (refit ? RTC_SCENE_FLAG_DYNAMIC : RTC_SCENE_FLAG_NONE) |
                                   (opts.count_filter ? RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION : RTC_SCENE_FLAG_NONE)));
    // Refit: Embree uses a geometry's own quality only under a LOW scene (two levels).
    rtcSetSceneBuildQuality(s.scene, refit                                 ? RTC_BUILD_QUALITY_LOW
                                     : opts.quality == EmbreeQuality::high ? RTC_BUILD_QUALITY_HIGH
                                                                           : RTC_BUILD_QUALITY_MEDIUM);
    s.check("rtcSetSceneBuildQuality");

    const std::int64_t before_buffers = s.mem_current.load();
    if (!mesh.triangles.empty()) {
        RTCGeometry geom = rtcNewGeometry(s.device, RTC_GEOMETRY_TYPE_TRIANGLE);
        s.check("rtcNewGeometry");
        rtcSetGeometryBuildQuality(geom, refit                                 ? RTC_BUILD_QUALITY_REFIT
                                         : opts.quality == EmbreeQuality::high ? RTC_BUILD_QUALITY_HIGH
                                                                               : RTC_BUILD_QUALITY_MEDIUM);
        // rtcSetNewGeometryBuffer over-allocates so the last vertex can be read
        // with a 16-byte load (Embree's padding requirement).
        auto* verts = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                  3 * sizeof(float), mesh.positions.size()));
        auto* index = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
            geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t), mesh.triangles.size()));
        if (s.failed.load() || !verts || !index) {
            rtcReleaseGeometry(geom);
            s.check("rtcSetNewGeometryBuffer");
            throw Error("Embree: rtcSetNewGeometryBuffer returned null");
        }
        static_assert(sizeof(Vec3) == 3 * sizeof(float) && sizeof(Triangle) == 3 * sizeof(std::uint32_t));
        std::memcpy(verts, mesh.positions.data(), mesh.positions.size() * sizeof(Vec3));
        std::memcpy(index, mesh.triangles.data(), mesh.triangles.size() * sizeof(Triangle));
        rtcCommitGeometry(geom);
        rtcAttachGeometryByID(s.scene, geom, 0);  // geomID 0: primID is our triangle id
        rtcReleaseGeometry(geom);                 // the scene holds it now
        s.check("rtcCommitGeometry");
    }
    const std::int64_t after_buffers = s.mem_current.load();
    s.stats.setup_ms = ms_since(t0);

    const auto t1 = Clock::now();
    rtcCommitScene(s.scene);
    s.stats.build_ms = ms_since(t1);
    s.check("rtcCommitScene");

    s.stats.memory_tracked = s.mem_seen.load();
    s.stats.buffer_bytes = after_buffers - before_buffers;
    s.stats.bvh_bytes = s.mem_current.load() - after_buffers;
    s.stats.peak_bytes = s.mem_peak.load();
    s.stats.bytes_per_triangle = mesh.size() == 0 ? 0.0 : double(s.stats.bvh_bytes) / double(mesh.size());
}

double EmbreeScene::update_vertices(const Mesh& mesh) {
    Impl& s = *impl_;
    validate(mesh);
    if (mesh.size() != s.stats.triangles)
        throw Error("Embree update_vertices: the mesh has " + std::to_string(mesh.size()) + " triangles, the scene " +
                    std::to_string(s.stats.triangles));
    if (mesh.triangles.empty()) return 0.0;
    RTCGeometry geom = rtcGetGeometry(s.scene, 0);
    s.check("rtcGetGeometry");
    const RTCBufferType kVertex = RTC_BUFFER_TYPE_VERTEX, kIndex = RTC_BUFFER_TYPE_INDEX;
    auto* verts = static_cast<float*>(rtcGetGeometryBufferData(geom, kVertex, 0));
    const auto* index = static_cast<const std::uint32_t*>(rtcGetGeometryBufferData(geom, kIndex, 0));
    s.check("rtcGetGeometryBufferData");
    if (!verts || !index || std::memcmp(index, mesh.triangles.data(), mesh.triangles.size() * sizeof(Triangle)) != 0)
        throw Error("Embree update_vertices: the triangles differ from the scene's");
    for (const Triangle& t : mesh.triangles)  // the vertex buffer keeps the size it was made with
        for (std::uint32_t v : t)
            if (v >= s.stats.vertices) throw Error("Embree update_vertices: more vertices than the scene's buffer");
    const auto t0 = Clock::now();
    std::memcpy(verts, mesh.positions.data(),
                std::min<std::size_t>(mesh.positions.size(), s.stats.vertices) * sizeof(Vec3));
    rtcUpdateGeometryBuffer(geom, kVertex, 0);
    rtcCommitGeometry(geom);
    rtcCommitScene(s.scene);
    const double ms = ms_since(t0);
    s.check("rtcCommitScene");
    return ms;
}

EmbreeScene::~EmbreeScene() = default;
EmbreeScene::EmbreeScene(EmbreeScene&&) noexcept = default;
EmbreeScene& EmbreeScene::operator=(EmbreeScene&&) noexcept = default;

const EmbreeOptions& EmbreeScene::options() const { return impl_->opts; }
const EmbreeStats& EmbreeScene::stats() const { return impl_->stats; }

std::string EmbreeScene::version() {
    return std::to_string(RTC_VERSION_MAJOR) + "." + std::to_string(RTC_VERSION_MINOR) + "." +
           std::to_string(RTC_VERSION_PATCH);
}

std::string EmbreeScene::tasking_system() const {
    switch (rtcGetDeviceProperty(impl_->device, RTC_DEVICE_PROPERTY_TASKING_SYSTEM)) {
    case 0: return "internal";
    case 1: return "tbb";
    case 2: return "ppl";
    default: return "unknown";
    }
}

namespace {

// count_hits: the context Embree passes to the filter, with the count after it.
struct CountContext {
    RTCIntersectContext ctx;
    std::uint32_t count = 0;
};

void count_and_reject(const RTCFilterFunctionNArguments* args) {
    auto* c = reinterpret_cast<CountContext*>(args->context);
    for (unsigned i = 0; i < args->N; ++i)
        if (args->valid[i] != 0) {
            ++c->count;
            args->valid[i] = 0;
        }
}

}  // namespace

bool EmbreeScene::passes(const Ray& r) const {
    switch (check_embree_ray(r)) {
    case EmbreeRayCheck::invalid: impl_->invalid.fetch_add(1, std::memory_order_relaxed); return false;
    case EmbreeRayCheck::unsupported: impl_->unsupported.fetch_add(1, std::memory_order_relaxed); return false;
    case EmbreeRayCheck::ok: break;
    }
    return true;
}

std::uint32_t EmbreeScene::count_hits(const Ray& r) const {
    if (!impl_->opts.count_filter) throw Error("EmbreeScene::count_hits needs EmbreeOptions::count_filter");
    if (!passes(r)) return 0;
    alignas(16) RTCRayHit rh = embree_ray_hit(r);
    CountContext c;
    rtcInitIntersectContext(&c.ctx);
    c.ctx.filter = &count_and_reject;
    rtcIntersect1(impl_->scene, &c.ctx, &rh);
    impl_->check("rtcIntersect1");
    return c.count;
}

Hit EmbreeScene::intersect(const Ray& r) const {
    if (!passes(r)) return Hit{};
    alignas(16) RTCRayHit rh = embree_ray_hit(r);
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    rtcIntersect1(impl_->scene, &ctx, &rh);
    impl_->check("rtcIntersect1");
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return Hit{};
    return Hit{rh.ray.tfar, rh.hit.u, rh.hit.v, rh.hit.primID};
}

bool EmbreeScene::occluded(const Ray& r) const {
    if (!passes(r)) return false;
    alignas(16) RTCRay ray = embree_ray_hit(r).ray;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    rtcOccluded1(impl_->scene, &ctx, &ray);
    impl_->check("rtcOccluded1");
    return ray.tfar == -std::numeric_limits<float>::infinity();  // Embree marks a hit with tfar = -inf
}

void EmbreeScene::intersect(std::span<const Ray> rays, std::span<Hit> hits) const {
    if (rays.size() != hits.size()) throw Error("EmbreeScene::intersect: rays and hits differ in size");
    for (std::size_t i = 0; i < rays.size(); ++i) hits[i] = intersect(rays[i]);
}

void EmbreeScene::occluded(std::span<const Ray> rays, std::span<std::uint8_t> out) const {
    if (rays.size() != out.size()) throw Error("EmbreeScene::occluded: rays and results differ in size");
    for (std::size_t i = 0; i < rays.size(); ++i) out[i] = occluded(rays[i]) ? 1 : 0;
}

namespace {
constexpr std::size_t kStream = 256;
}

void EmbreeScene::intersect_stream(std::span<const Ray> rays, std::span<Hit> hits, bool coherent) const {
    if (rays.size() != hits.size()) throw Error("EmbreeScene::intersect_stream: rays and hits differ in size");
    std::vector<RTCRayHit> rh(std::min(rays.size(), kStream));
    for (std::size_t b = 0; b < rays.size(); b += kStream) {
        const std::size_t n = std::min(kStream, rays.size() - b);
        for (std::size_t i = 0; i < n; ++i) {
            rh[i] = embree_ray_hit(rays[b + i]);
            if (!passes(rays[b + i])) {  // an empty interval: Embree skips the ray
                rh[i].ray.tnear = 1.0f;
                rh[i].ray.tfar = 0.0f;
            }
        }
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        if (coherent) ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        rtcIntersect1M(impl_->scene, &ctx, rh.data(), unsigned(n), sizeof(RTCRayHit));
        impl_->check("rtcIntersect1M");
        for (std::size_t i = 0; i < n; ++i)
            hits[b + i] = rh[i].hit.geomID == RTC_INVALID_GEOMETRY_ID
                              ? Hit{}
                              : Hit{rh[i].ray.tfar, rh[i].hit.u, rh[i].hit.v, rh[i].hit.primID};
    }
}

void EmbreeScene::occluded_stream(std::span<const Ray> rays, std::span<std::uint8_t> out, bool coherent) const {
    if (rays.size() != out.size()) throw Error("EmbreeScene::occluded_stream: rays and results differ in size");
    std::vector<RTCRay> r(std::min(rays.size(), kStream));
    for (std::size_t b = 0; b < rays.size(); b += kStream) {
        const std::size_t n = std::min(kStream, rays.size() - b);
        for (std::size_t i = 0; i < n; ++i) {
            r[i] = embree_ray_hit(rays[b + i]).ray;
            if (!passes(rays[b + i])) {
                r[i].tnear = 1.0f;
                r[i].tfar = 0.0f;
            }
        }
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        if (coherent) ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        rtcOccluded1M(impl_->scene, &ctx, r.data(), unsigned(n), sizeof(RTCRay));
        impl_->check("rtcOccluded1M");
        for (std::size_t i = 0; i < n; ++i) out[b + i] = r[i].tfar == -std::numeric_limits<float>::infinity() ? 1 : 0;
    }
}

namespace {
// Lane k of an RTCRayHit8 from a single-ray RTCRayHit (the same conversion as every other call).
void set_lane(RTCRayHit8& p, int k, const RTCRayHit& one) {
    p.ray.org_x[k] = one.ray.org_x, p.ray.org_y[k] = one.ray.org_y, p.ray.org_z[k] = one.ray.org_z;
    p.ray.dir_x[k] = one.ray.dir_x, p.ray.dir_y[k] = one.ray.dir_y, p.ray.dir_z[k] = one.ray.dir_z;
    p.ray.tnear[k] = one.ray.tnear, p.ray.tfar[k] = one.ray.tfar, p.ray.time[k] = one.ray.time;
    p.ray.mask[k] = one.ray.mask, p.ray.id[k] = one.ray.id, p.ray.flags[k] = one.ray.flags;
    p.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
    p.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
}

// Rays [b, b + 8) (fewer at the end) into a packet; valid: -1 for the rays
// Embree can take (passes), 0 for the others and past the end. Returns the count.
template <class Passes>
std::size_t fill_packet8(RTCRayHit8& p, int* valid, std::span<const Ray> rays, std::size_t b, Passes passes) {
    const std::size_t n = std::min<std::size_t>(8, rays.size() - b);
    for (int k = 0; k < 8; ++k) {
        const bool live = std::size_t(k) < n && passes(rays[b + std::size_t(k)]);
        valid[k] = live ? -1 : 0;
        set_lane(p, k, embree_ray_hit(live ? rays[b + std::size_t(k)] : rays[b]));
    }
    return n;
}
}  // namespace

namespace {
// Packets of 8 consecutive rays (coherent context): call(valid, ctx, packet)
// runs the Embree call, store(k, valid, packet) reads lane k back.
template <class Passes, class Call, class Store>
void for_packets8(std::span<const Ray> rays, Passes passes, Call call, Store store) {
    for (std::size_t b = 0; b < rays.size(); b += 8) {
        alignas(32) RTCRayHit8 p;
        alignas(32) int valid[8];
        const std::size_t n = fill_packet8(p, valid, rays, b, passes);
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        call(valid, &ctx, p);
        for (std::size_t k = 0; k < n; ++k) store(b + k, valid[k] != 0, p, int(k));
    }
}
}  // namespace

void EmbreeScene::intersect_packets8(std::span<const Ray> rays, std::span<Hit> hits) const {
    if (rays.size() != hits.size()) throw Error("EmbreeScene::intersect_packets8: rays and hits differ in size");
    for_packets8(
        rays, [&](const Ray& r) { return passes(r); },
        [&](int* valid, RTCIntersectContext* ctx, RTCRayHit8& p) {
            rtcIntersect8(valid, impl_->scene, ctx, &p);
            impl_->check("rtcIntersect8");
        },
        [&](std::size_t i, bool live, const RTCRayHit8& p, int k) {
            hits[i] = !live || p.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID
                          ? Hit{}
                          : Hit{p.ray.tfar[k], p.hit.u[k], p.hit.v[k], p.hit.primID[k]};
        });
}

void EmbreeScene::occluded_packets8(std::span<const Ray> rays, std::span<std::uint8_t> out) const {
    if (rays.size() != out.size()) throw Error("EmbreeScene::occluded_packets8: rays and results differ in size");
    for_packets8(
        rays, [&](const Ray& r) { return passes(r); },
        [&](int* valid, RTCIntersectContext* ctx, RTCRayHit8& p) {
            rtcOccluded8(valid, impl_->scene, ctx, &p.ray);
            impl_->check("rtcOccluded8");
        },
        [&](std::size_t i, bool live, const RTCRayHit8& p, int k) {
            out[i] = live && p.ray.tfar[k] == -std::numeric_limits<float>::infinity() ? 1 : 0;
        });
}

std::uint64_t EmbreeScene::invalid_rays() const { return impl_->invalid.load(); }
std::uint64_t EmbreeScene::unsupported_rays() const { return impl_->unsupported.load(); }
void EmbreeScene::reset_counters() {
    impl_->invalid.store(0);
    impl_->unsupported.store(0);
}

}  // namespace simdbvh::reference
