// Deterministic ray generation: pinhole camera, incoherent rays, diffuse
// bounces. Float math with + - * /, sqrt, sin and cos only; own PRNG (except
// interior_rays: std::mt19937_64 and libstdc++'s normal distribution, as the
// scene bench has always drawn them).
#include "simdbvh/workloads/rays.h"

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <utility>

#include "rng.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/workloads/families.h"

namespace simdbvh::workloads {
namespace {

constexpr float kTwoPi = 6.28318530717958648f;
constexpr float kTanHalfFov = 0.414213562f;  // tan(22.5 deg): 45 deg vertical field of view
constexpr float kSinHalfFov = 0.382683432f;  // sin(22.5 deg)

// Empty or non-finite bounds fall back to the cube [-1, 1]^3.
Aabb usable(const Aabb& b) {
    if (b.is_empty() || !is_finite(b.lo) || !is_finite(b.hi)) return Aabb{{-1, -1, -1}, {1, 1, 1}};
    return b;
}

// Half the bounds' diagonal. Where the float products overflow (extents beyond about 1e19) it is taken in
// double and capped at the largest float, so huge scenes keep their scale instead of falling to 1.
float half_diagonal(const Aabb& b) {
    const float r = 0.5f * length(b.extent());
    if (r > 0.0f && std::isfinite(r)) return r;
    if (!std::isinf(r)) return 1.0f;  // a point (or nothing): unit scale
    double sum = 0;
    for (int k = 0; k < 3; ++k) {
        const double e = double(b.hi[k]) - double(b.lo[k]);
        sum += e * e;
    }
    return float(std::fmin(0.5 * std::sqrt(sum), double(std::numeric_limits<float>::max())));
}

bool is_zero(Vec3 v) { return v.x == 0.0f && v.y == 0.0f && v.z == 0.0f; }

// normalize(d), unless its float products overflow (|d| beyond about 1e19: a zero vector) or underflow (a
// non-finite one): then in double. Every direction the float path gets right is kept bit for bit.
Vec3 unit(Vec3 d) {
    const Vec3 n = normalize(d);
    if (is_finite(n) && !is_zero(n)) return n;
    const double x = d.x, y = d.y, z = d.z, l = std::sqrt(x * x + y * y + z * z);
    if (!(l > 0.0) || !std::isfinite(l)) return n;  // zero or non-finite: the caller's to refuse
    return Vec3{float(x / l), float(y / l), float(z / l)};
}

// The direction from `from` to `to` (unit); the difference in double when it overflows floats.
Vec3 unit_between(Vec3 from, Vec3 to) {
    const Vec3 d = to - from;
    if (is_finite(d)) return unit(d);
    const double x = double(to.x) - double(from.x), y = double(to.y) - double(from.y),
                 z = double(to.z) - double(from.z);
    const double l = std::sqrt(x * x + y * y + z * z);
    return Vec3{float(x / l), float(y / l), float(z / l)};
}

// a + b * s in double, each component clamped to the float range: a point as far out as floats reach.
Vec3 clamped_point(Vec3 a, Vec3 b, double s) {
    constexpr double kMax = std::numeric_limits<float>::max();
    Vec3 out;
    for (int k = 0; k < 3; ++k) out[k] = float(std::fmax(-kMax, std::fmin(kMax, double(a[k]) + double(b[k]) * s)));
    return out;
}

// The bounds' centre and a point at fractions u of the extent, in double where the float sums overflow.
Vec3 wide_center(const Aabb& b) {
    Vec3 c;
    for (int k = 0; k < 3; ++k) c[k] = float(0.5 * (double(b.lo[k]) + double(b.hi[k])));
    return c;
}

// Duff et al. 2017, "Building an Orthonormal Basis, Revisited".
void onb(Vec3 n, Vec3& t, Vec3& b) {
    const float s = std::copysign(1.0f, n.z);
    const float a = -1.0f / (s + n.z);
    const float c = n.x * n.y * a;
    t = Vec3{1.0f + s * n.x * n.x * a, s * c, -s * n.x};
    b = Vec3{c, s + n.y * n.y * a, -n.y};
}

}  // namespace

std::string_view name(RayKind k) {
    switch (k) {
    case RayKind::primary: return "primary";
    case RayKind::incoherent: return "incoherent";
    case RayKind::diffuse: return "diffuse";
    case RayKind::diffuse_shuffled: return "diffuse-shuffled";
    case RayKind::shadow: return "shadow";
    case RayKind::area_shadow: return "area-shadow";
    case RayKind::ao: return "ao";
    case RayKind::lidar: return "lidar";
    }
    return "?";
}

std::optional<RayKind> parse_ray_kind(std::string_view s) {
    for (RayKind k : kRayKinds)
        if (s == name(k)) return k;
    return std::nullopt;
}

std::string ray_kind_names() {
    std::string s;
    for (RayKind k : kRayKinds) {
        if (!s.empty()) s += ", ";
        s += name(k);
    }
    return s;
}

bool needs_primary_hits(RayKind k) {
    return k == RayKind::diffuse || k == RayKind::diffuse_shuffled || k == RayKind::shadow ||
           k == RayKind::area_shadow || k == RayKind::ao;
}

Camera default_camera(const Aabb& bounds_in, int width, int height) {
    if (width <= 0 || height <= 0) throw Error("camera size must be positive");
    const Aabb b = usable(bounds_in);
    const Vec3 c = b.center();
    const float r = half_diagonal(b);
    // 3/4 view from the +x, +y, +z side, somewhat above; far enough that the
    // bounding sphere fits the vertical field of view.
    const Vec3 view = normalize(Vec3{1.0f, 0.6f, 1.2f});
    Camera cam;
    cam.eye = c + view * (r / kSinHalfFov);
    if (!is_finite(cam.eye) || !is_finite(c)) {
        // Huge bounds: the eye along the same view, as far out as floats reach (closer than the bounding
        // sphere needs, so the picture shows the middle of the scene).
        const Vec3 wc = wide_center(b);
        double dist = double(r) / double(kSinHalfFov);
        for (int k = 0; k < 3; ++k)
            if (view[k] != 0.0f)
                dist = std::fmin(dist, (double(std::numeric_limits<float>::max()) - std::fabs(double(wc[k]))) /
                                           std::fabs(double(view[k])));
        cam.eye = clamped_point(wc, view, dist);
        cam.forward = unit_between(cam.eye, wc);
        if (!is_finite(cam.forward) || is_zero(cam.forward)) cam.forward = view * -1.0f;
    } else {
        cam.forward = unit(c - cam.eye);
    }
    const Vec3 right = normalize(cross(cam.forward, Vec3{0.0f, 1.0f, 0.0f}));
    const Vec3 up = cross(right, cam.forward);
    cam.right = right * (kTanHalfFov * float(width) / float(height));
    cam.up = up * kTanHalfFov;
    cam.width = width;
    cam.height = height;
    return cam;
}

std::vector<Ray> primary_rays(const Camera& cam) {
    std::vector<Ray> rays;
    rays.reserve(std::size_t(cam.width) * std::size_t(cam.height));
    for (int y = 0; y < cam.height; ++y) {
        const float py = 1.0f - (float(y) + 0.5f) / float(cam.height) * 2.0f;
        for (int x = 0; x < cam.width; ++x) {
            const float px = (float(x) + 0.5f) / float(cam.width) * 2.0f - 1.0f;
            Ray r;
            r.org = cam.eye;
            r.dir = unit(cam.forward + cam.right * px + cam.up * py);
            rays.push_back(r);
        }
    }
    return rays;
}

std::vector<Ray> incoherent_rays(const Aabb& bounds_in, std::size_t count, std::uint64_t seed) {
    const Aabb b = usable(bounds_in);
    const Vec3 c = b.center(), e = b.extent();
    const float radius = 1.5f * half_diagonal(b);
    const double wide_radius = 1.5 * double(half_diagonal(b));  // where `radius` overflows
    detail::Rng rng(seed);
    std::vector<Ray> rays;
    rays.reserve(count);
    while (rays.size() < count) {
        // Uniform direction on the sphere (z uniform in [-1, 1], angle uniform).
        const float z = 1.0f - 2.0f * rng.uniform();
        const float phi = kTwoPi * rng.uniform();
        const float s = std::sqrt(std::fmax(0.0f, 1.0f - z * z));
        const Vec3 on_sphere{s * std::cos(phi), s * std::sin(phi), z};
        const Vec3 u{rng.uniform(), rng.uniform(), rng.uniform()};
        Vec3 o = c + on_sphere * radius;
        Vec3 target = b.lo + Vec3{e.x * u.x, e.y * u.y, e.z * u.z};
        if (!is_finite(o) || !is_finite(target)) {
            // Bounds near the float range: the sums overflow. The same points in double, clamped to floats.
            o = clamped_point(wide_center(b), on_sphere, wide_radius);
            for (int k = 0; k < 3; ++k)
                target[k] = float(double(b.lo[k]) + (double(b.hi[k]) - double(b.lo[k])) * double(u[k]));
        }
        if (o.x == target.x && o.y == target.y && o.z == target.z) continue;  // no direction: draw again
        Ray r;
        r.org = o;
        r.dir = unit_between(o, target);
        rays.push_back(r);
    }
    return rays;
}

namespace {

// The primary hits rays start from: the hit rays' ids, checked, and the scale of the origin offset.
struct SurfaceStarts {
    std::vector<std::size_t> ids;
    float scale = 1.0f;  // the largest |coordinate| of the bounds (the offset near the origin)
};

SurfaceStarts surface_starts(const char* what, const Mesh& mesh, std::span<const Ray> primary,
                             std::span<const Hit> hits) {
    if (primary.size() != hits.size())
        throw Error(std::string(what) + ": " + std::to_string(primary.size()) + " rays but " +
                    std::to_string(hits.size()) + " hits");
    SurfaceStarts s;
    for (std::size_t i = 0; i < hits.size(); ++i) {
        if (!hits[i].hit()) continue;
        if (hits[i].prim >= mesh.triangles.size())
            throw Error(std::string(what) + ": hit " + std::to_string(i) + " names triangle " +
                        std::to_string(hits[i].prim) + " of " + std::to_string(mesh.triangles.size()));
        s.ids.push_back(i);
    }
    const Aabb b = usable(mesh.bounds());
    float scale = 0.0f;
    for (int k = 0; k < 3; ++k) scale = std::fmax(scale, std::fmax(std::fabs(b.lo[k]), std::fabs(b.hi[k])));
    s.scale = scale > 0.0f ? scale : 1.0f;
    return s;
}

// The hit point of primary ray i, its geometric normal facing the incoming ray, and the offset origin.
struct SurfacePoint {
    Vec3 p, ng, org;
};

SurfacePoint surface_point(const Mesh& mesh, const Ray& primary, const Hit& h, float scale) {
    const Vec3 v0 = mesh.vertex(h.prim, 0), v1 = mesh.vertex(h.prim, 1), v2 = mesh.vertex(h.prim, 2);
    SurfacePoint s;
    s.p = v0 * (1.0f - h.u - h.v) + v1 * h.u + v2 * h.v;
    Vec3 ng = cross(v1 - v0, v2 - v0);
    const float len = length(ng);
    ng = len > 0.0f && std::isfinite(len) ? ng * (1.0f / len) : normalize(primary.dir * -1.0f);
    if (dot(ng, primary.dir) > 0.0f) ng = ng * -1.0f;  // face the incoming ray
    s.ng = ng;
    s.org = offset_ray_origin(s.p, ng, scale);  // Wachter and Binder, RT Gems ch. 6
    return s;
}

// Cosine-weighted hemisphere about n (Malley's method).
Vec3 cosine_direction(Vec3 n, detail::Rng& rng) {
    Vec3 t, bt;
    onb(n, t, bt);
    const float u1 = rng.uniform(), u2 = rng.uniform();
    const float r = std::sqrt(u1), phi = kTwoPi * u2;
    const float lz = std::sqrt(std::fmax(0.0f, 1.0f - u1));
    return normalize(t * (r * std::cos(phi)) + bt * (r * std::sin(phi)) + n * lz);
}

std::vector<Ray> bounces(const char* what, const Mesh& mesh, std::span<const Ray> primary, std::span<const Hit> hits,
                         std::size_t count, std::uint64_t seed, float tmax) {
    const SurfaceStarts starts = surface_starts(what, mesh, primary, hits);
    std::vector<Ray> rays;
    if (starts.ids.empty()) return rays;  // nothing was hit: no bounces
    detail::Rng rng(seed);
    rays.reserve(count);
    for (std::size_t n = 0; n < count; ++n) {
        const std::size_t i = starts.ids[n % starts.ids.size()];
        const SurfacePoint s = surface_point(mesh, primary[i], hits[i], starts.scale);
        Ray ray;
        ray.org = s.org;
        ray.dir = cosine_direction(s.ng, rng);
        ray.tmax = tmax;
        rays.push_back(ray);
    }
    return rays;
}

}  // namespace

std::vector<Ray> diffuse_rays(const Mesh& mesh, std::span<const Ray> primary, std::span<const Hit> hits,
                              std::size_t count, std::uint64_t seed) {
    return bounces("diffuse_rays", mesh, primary, hits, count, seed, std::numeric_limits<float>::infinity());
}

std::vector<Ray> ao_rays(const Mesh& mesh, std::span<const Ray> primary, std::span<const Hit> hits, std::size_t count,
                         std::uint64_t seed) {
    return bounces("ao_rays", mesh, primary, hits, count, seed, 0.1f * half_diagonal(usable(mesh.bounds())));
}

std::vector<Ray> shuffled(std::vector<Ray> rays, std::uint64_t seed) {
    detail::Rng rng(seed ^ 0x5bd1e995u);
    for (std::size_t i = rays.size(); i > 1; --i) std::swap(rays[i - 1], rays[rng.below(std::uint32_t(i))]);
    return rays;
}

Vec3 light_position(const Aabb& bounds) {
    const Aabb b = usable(bounds);
    const float r = half_diagonal(b);
    // Above the bounds and off to one side, as a sun-like key light: the shadow rays cross the scene at a slant.
    return b.center() + Vec3{0.4f * r, 1.5f * r, 0.3f * r};
}

std::vector<Ray> shadow_rays(const Mesh& mesh, std::span<const Ray> primary, std::span<const Hit> hits,
                             std::size_t count, std::uint64_t seed, bool area) {
    const SurfaceStarts starts = surface_starts("shadow_rays", mesh, primary, hits);
    std::vector<Ray> rays;
    if (starts.ids.empty()) return rays;
    const Vec3 light = light_position(mesh.bounds());
    const float side = half_diagonal(usable(mesh.bounds()));
    detail::Rng rng(seed);
    rays.reserve(count);
    for (std::size_t n = 0; n < count; ++n) {
        const std::size_t i = starts.ids[n % starts.ids.size()];
        const SurfacePoint s = surface_point(mesh, primary[i], hits[i], starts.scale);
        Vec3 target = light;
        if (area) target = light + Vec3{side * (rng.uniform() - 0.5f), 0.0f, side * (rng.uniform() - 0.5f)};
        const Vec3 d = target - s.org;
        const float dist = length(d);
        if (!(dist > 0.0f) || !std::isfinite(dist)) continue;
        Ray ray;
        ray.org = s.org;
        ray.dir = d * (1.0f / dist);
        ray.tmax = dist * 0.9999f;  // stop short of the light's own position
        rays.push_back(ray);
    }
    return rays;
}

std::vector<Ray> lidar_rays(const Aabb& bounds, std::size_t count) {
    constexpr int kBeams = 64;
    constexpr float kDeg = 0.0174532925f;
    const Aabb b = usable(bounds);
    const Vec3 o = b.center();
    const std::size_t steps = (count + kBeams - 1) / kBeams;
    std::vector<Ray> rays;
    rays.reserve(count);
    for (std::size_t a = 0; a < steps && rays.size() < count; ++a) {
        const float az = kTwoPi * (float(a) / float(steps));
        const float ca = std::cos(az), sa = std::sin(az);
        for (int k = 0; k < kBeams && rays.size() < count; ++k) {
            const float el = (-25.0f + 40.0f * float(k) / float(kBeams - 1)) * kDeg;
            const float ce = std::cos(el);
            Ray ray;
            ray.org = o;
            ray.dir = normalize(Vec3{ce * ca, std::sin(el), ce * sa});
            rays.push_back(ray);
        }
    }
    return rays;
}

std::vector<Ray> interior_rays(const Aabb& b, std::size_t n, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::normal_distribution<float> g(0.0f, 1.0f);
    std::vector<Ray> rays(n);
    const Vec3 e = b.extent();
    for (Ray& r : rays) {
        r.org = b.lo + Vec3{u(rng) * e.x, u(rng) * e.y, u(rng) * e.z};
        Vec3 d{0, 0, 0};
        while (length(d) < 1e-3f) d = Vec3{g(rng), g(rng), g(rng)};
        r.dir = d * (1.0f / length(d));
        r.tmin = 0.0f;
        r.tmax = std::numeric_limits<float>::infinity();
    }
    return rays;
}

}  // namespace simdbvh::workloads
