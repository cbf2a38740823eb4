#pragma once
// Embree 3 as a comparison method: one device and one scene per mesh, built
// with a chosen quality and robustness, traced one ray at a time
// (rtcIntersect1 / rtcOccluded1) so it runs the same kind of loop as ours.
//
// Rays Embree must not see (Debian's Embree 3 has its assertions on and aborts):
//  - invalid rays (simdbvh::prepare(r).valid is false: NaN/Inf components,
//    zero direction, NaN or empty interval) are misses by definition; counted
//    in invalid_rays();
//  - valid rays outside Embree's domain (tmin < 0, or a component of org/dir
//    beyond Embree's FLT_LARGE = 1.844e18) are answered as misses without
//    asking Embree; counted in unsupported_rays(). Generated rays never are.
// Results use our conventions: Hit{t, u, v, prim}, P = (1-u-v) v0 + u v1 + v v2
// (Embree's convention too); a miss is Hit{} (t = +inf, prim = kInvalidPrim).
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "simdbvh/kernels/hit.h"
#include "simdbvh/kernels/ray.h"
#include "simdbvh/kernels/mesh.h"

namespace simdbvh::reference {

// RTC_BUILD_QUALITY_MEDIUM / _HIGH; refit: a dynamic scene (RTC_SCENE_FLAG_DYNAMIC,
// scene quality LOW) whose geometry has RTC_BUILD_QUALITY_REFIT, so that
// update_vertices() refits instead of rebuilding.
enum class EmbreeQuality : std::uint8_t { medium, high, refit };
std::string_view name(EmbreeQuality q);
std::optional<EmbreeQuality> parse_embree_quality(std::string_view s);

struct EmbreeOptions {
    EmbreeQuality quality = EmbreeQuality::medium;
    bool robust = false;        // RTC_SCENE_FLAG_ROBUST (watertight-ish test, no culling of thin boxes)
    int threads = 0;            // device config "threads=N"; 0: Embree's default (all hardware threads)
    bool count_filter = false;  // RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION, which count_hits() needs
};
// "embree-medium", "embree-high-robust", ... (for tables and chart legends).
std::string method_name(const EmbreeOptions& o);

struct EmbreeStats {
    double setup_ms = 0;  // device + scene + geometry buffers (copying the mesh)
    double build_ms = 0;  // rtcCommitScene only
    int threads = 0;      // threads the device was configured with (resolved when options.threads == 0)
    std::size_t triangles = 0;
    std::size_t vertices = 0;  // the vertex buffer's size (fixed at construction)
    // From rtcSetDeviceMemoryMonitorFunction (bytes Embree allocated minus freed):
    bool memory_tracked = false;    // false when the monitor never fired
    std::int64_t buffer_bytes = 0;  // vertex + index buffers (Embree's copy of the mesh)
    std::int64_t bvh_bytes = 0;     // kept after commit, minus buffers: the BVH incl. its triangle blocks
    std::int64_t peak_bytes = 0;    // peak total during setup + build (temporaries included)
    double bytes_per_triangle = 0;  // bvh_bytes / triangles (comparable to our BuildStats)
};

class EmbreeScene {
public:
    // Validates the mesh (throws simdbvh::Error), copies it into Embree buffers
    // and builds. Embree errors become simdbvh::Error with Embree's message.
    explicit EmbreeScene(const Mesh& mesh, const EmbreeOptions& opts = {});
    ~EmbreeScene();
    EmbreeScene(EmbreeScene&&) noexcept;
    EmbreeScene& operator=(EmbreeScene&&) noexcept;
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    const EmbreeOptions& options() const;
    const EmbreeStats& stats() const;
    // Embree's version, e.g. "3.13.5", and tasking system ("internal", "tbb", "ppl").
    static std::string version();
    std::string tasking_system() const;

    // Moved vertices, the same triangles: copies the positions into Embree's
    // vertex buffer and commits (a refit with EmbreeQuality::refit, else a
    // rebuild). Returns the milliseconds of copy + commit. Another triangle
    // list or more vertices than the buffer holds throws simdbvh::Error.
    double update_vertices(const Mesh& mesh);

    // Closest hit: rtcIntersect1. Safe to call from several threads.
    Hit intersect(const Ray& ray) const;
    // Any hit: rtcOccluded1 reports only hit/miss (no triangle, no t).
    bool occluded(const Ray& ray) const;
    // Batches (one rtc*1 call per ray); sizes must match (throws simdbvh::Error).
    void intersect(std::span<const Ray> rays, std::span<Hit> hits) const;
    void occluded(std::span<const Ray> rays, std::span<std::uint8_t> occluded) const;  // 1 = occluded
    // Batches through Embree's stream API (rtcIntersect1M / rtcOccluded1M, 256
    // rays per call, default context flags), as Open3D's RaycastingScene calls
    // it: Embree may trace coherent rays of a stream as packets, which its
    // single-ray calls cannot. The same answers as the calls above.
    // coherent: the context flag RTC_INTERSECT_CONTEXT_FLAG_COHERENT (Embree's
    // hint for coherent rays, e.g. a camera's in image order); else the default
    // (incoherent).
    void intersect_stream(std::span<const Ray> rays, std::span<Hit> hits, bool coherent = false) const;
    void occluded_stream(std::span<const Ray> rays, std::span<std::uint8_t> occluded, bool coherent = false) const;
    // Packets of 8 consecutive rays through rtcIntersect8 / rtcOccluded8 (the
    // context flagged coherent), Embree's packet API, beside our packets.
    void intersect_packets8(std::span<const Ray> rays, std::span<Hit> hits) const;
    void occluded_packets8(std::span<const Ray> rays, std::span<std::uint8_t> occluded) const;

    // Every hit along the ray, counted the way Open3D's RaycastingScene
    // counts intersections: rtcIntersect1 with a context filter that counts
    // each reported hit and rejects it, so traversal goes on. A ray through a
    // shared edge or vertex may be reported by several triangles or by none;
    // that is what this method is here to measure. Needs
    // EmbreeOptions::count_filter (else throws simdbvh::Error); invalid and
    // unsupported rays count 0.
    std::uint32_t count_hits(const Ray& ray) const;

    // Rays not passed to Embree since construction (or the last reset).
    std::uint64_t invalid_rays() const;
    std::uint64_t unsupported_rays() const;
    void reset_counters();

private:
    bool passes(const Ray& ray) const;  // check_embree_ray ok; else counts it and false
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// Whether Embree may be called with this ray (see the top of this file).
enum class EmbreeRayCheck : std::uint8_t { ok, invalid, unsupported };
EmbreeRayCheck check_embree_ray(const Ray& ray);

}  // namespace simdbvh::reference
