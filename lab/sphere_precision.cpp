// SPDX-License-Identifier: MIT
// The sphere precision study (sphere_precision.h): rays aimed at a distant
// unit sphere, intersected by the naive float quadratic, hit_sphere and Embree.
#include "lab.h"
#include "sphere_precision.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <span>

#include "simdbvh/reference/embree_instances.h"
#include "simdbvh/scene/scene.h"
#include "simdbvh/scene/shapes.h"

namespace simdbvh::lab {

namespace {

constexpr std::uint64_t kSeed = 0x5a4e'0014'0000'0000ull;  // fixed: the study's rays are the same in every run
constexpr int kRatioSteps = 28;                            // 10^(k/4), k = 1..28
constexpr double kAimRadius = 0.9;                         // of the radius
constexpr int kMaxDraws = 1000;                            // per ray, before giving up on a hitting direction
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

using LD = long double;
struct V3 {
    LD x, y, z;
};
V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 operator*(LD s, V3 a) { return {s * a.x, s * a.y, s * a.z}; }
LD dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
V3 unit(V3 a) { return (1.0L / std::sqrt(dot(a, a))) * a; }
V3 wide(Vec3 v) { return {v.x, v.y, v.z}; }
Vec3 to_float(V3 v) { return {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)}; }

// Uniform doubles from the 64-bit Mersenne Twister's bits (the standard fixes those, not the distributions).
class Rng {
public:
    explicit Rng(std::uint64_t seed) : g_(seed) {}
    double uniform() { return static_cast<double>(g_() >> 11) * 0x1p-53; }  // [0, 1)
    double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
    V3 unit_vector() {  // rejection from the cube into the ball
        for (;;) {
            const V3 p{uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)};
            const LD n = dot(p, p);
            if (n > 1e-4L && n <= 1.0L) return unit(p);
        }
    }

private:
    std::mt19937_64 g_;
};

// Whether the float ray hits the float sphere in exact arithmetic (long double: the inputs are floats, so the
// closest-approach distance below is accurate far beyond what decides the answer here).
bool hits_exactly(const Ray& ray, const Sphere& s) {
    const V3 f = wide(ray.org) - wide(s.center), d = wide(ray.dir);
    const LD rr = LD(s.radius) * LD(s.radius);
    const LD tc = -dot(f, d) / dot(d, d);  // closest approach
    const V3 l = f + tc * d;
    return dot(f, f) > rr && tc > 0 && dot(l, l) <= rr;  // origin outside, sphere ahead, within a radius
}

// The textbook quadratic, all in float: a t^2 + b t + c = 0.
bool naive_hit(const Ray& ray, const Sphere& s, float* t) {
    const Vec3 f = ray.org - s.center, d = ray.dir;
    const float a = dot(d, d);
    const float b = 2.0f * dot(f, d);
    const float c = dot(f, f) - s.radius * s.radius;
    const float disc = b * b - 4.0f * a * c;
    if (disc < 0.0f) return false;
    const float sq = std::sqrt(disc);
    const float t0 = (-b - sq) / (2.0f * a);
    const float t1 = (-b + sq) / (2.0f * a);
    if (t0 >= 0.0f) *t = t0;
    else if (t1 >= 0.0f) *t = t1;
    else return false;
    return true;
}

bool robust_hit(const Ray& ray, const Sphere& s, float* t) {
    const PreparedRay p = prepare(ray);
    float tk = 0.0f, u = 0.0f, v = 0.0f;
    if (!p.valid || !hit_sphere(p, s, p.tmax, &tk, &u, &v)) return false;
    *t = to_caller_t(p, tk);
    return true;
}

// | |o + t d - c| - r | / r from the float t.
double hit_error(const Ray& ray, const Sphere& s, float t) {
    const V3 p = wide(ray.org) + LD(t) * wide(ray.dir);
    const V3 e = p - wide(s.center);
    return static_cast<double>(std::fabs(std::sqrt(dot(e, e)) - LD(s.radius)) / LD(s.radius));
}

// The misses and the hits' errors of one method at one ratio.
struct Tally {
    std::size_t misses = 0;
    std::vector<double> errors;

    void add(bool hit, const Ray& ray, const Sphere& s, float t) {
        if (hit) errors.push_back(hit_error(ray, s, t));
        else ++misses;
    }
    double miss_fraction(std::size_t rays) const { return rays ? double(misses) / double(rays) : kNaN; }
    double median() {
        if (errors.empty()) return kNaN;
        std::sort(errors.begin(), errors.end());
        const std::size_t n = errors.size();
        return n % 2 ? errors[n / 2] : 0.5 * (errors[n / 2 - 1] + errors[n / 2]);
    }
    double max() const { return errors.empty() ? kNaN : *std::max_element(errors.begin(), errors.end()); }
};

SpherePrecisionRow study_ratio(double ratio, std::size_t n, Rng& rng) {
    const Vec3 o = to_float(V3{rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)});
    const V3 axis0 = rng.unit_vector();
    const Sphere sphere{to_float(wide(o) + LD(ratio) * axis0), 1.0f};
    // The disc's frame around the float centre as seen from the float origin.
    const V3 c = wide(sphere.center), axis = unit(c - wide(o));
    const V3 helper = std::fabs(axis.x) < 0.6L ? V3{1, 0, 0} : V3{0, 1, 0};
    const V3 e1 = unit(cross(axis, helper)), e2 = cross(axis, e1);

    std::vector<Ray> rays(n);
    for (std::size_t i = 0; i < n; ++i) {
        Ray& ray = rays[i];
        ray.org = o;
        for (int draw = 0; draw < kMaxDraws; ++draw) {
            const LD rho = kAimRadius * LD(sphere.radius) * std::sqrt(LD(rng.uniform()));  // uniform over the disc
            const LD phi = 2.0L * 3.14159265358979323846264338327950288L * LD(rng.uniform());
            const V3 aim = c + (rho * std::cos(phi)) * e1 + (rho * std::sin(phi)) * e2;
            const V3 d = aim - wide(o);
            ray.dir = to_float(i % 2 ? unit(d) : d);
            if (hits_exactly(ray, sphere)) break;
        }
    }

    Tally naive, robust, embree;
    for (const Ray& ray : rays) {
        float t = 0.0f;
        const bool hn = naive_hit(ray, sphere, &t);
        naive.add(hn, ray, sphere, t);
        const bool hr = robust_hit(ray, sphere, &t);
        robust.add(hr, ray, sphere, t);
    }
    SceneDesc desc;
    desc.geometries.push_back(SphereSet{{sphere}});
    desc.instances.push_back(Instance{0, Affine3{}});
    const reference::EmbreeInstanceScene scene(desc);
    std::vector<SceneHit> hits(n);
    scene.intersect(rays, hits);
    for (std::size_t i = 0; i < n; ++i) embree.add(hits[i].hit(), rays[i], sphere, hits[i].t);

    SpherePrecisionRow row{};
    row.ratio = ratio;
    row.rays = n;
    row.miss_naive = naive.miss_fraction(n);
    row.miss_robust = robust.miss_fraction(n);
    row.miss_embree = embree.miss_fraction(n);
    row.median_err_naive = naive.median();
    row.median_err_robust = robust.median();
    row.median_err_embree = embree.median();
    row.max_err_naive = naive.max();
    row.max_err_robust = robust.max();
    row.max_err_embree = embree.max();
    return row;
}

}  // namespace

std::vector<SpherePrecisionRow> sphere_precision_study(std::size_t rays_per_ratio) {
    std::vector<SpherePrecisionRow> rows;
    for (int k = 1; k <= kRatioSteps; ++k) {
        Rng rng(kSeed + static_cast<std::uint64_t>(k));  // each ratio on its own stream
        rows.push_back(study_ratio(std::pow(10.0, k / 4.0), rays_per_ratio, rng));
    }
    return rows;
}

Json sphere_precision_json(const std::vector<SpherePrecisionRow>& rows) {
    Json a = Json::array();
    for (const SpherePrecisionRow& r : rows) {
        Json j;
        j["ratio"] = r.ratio;
        j["rays"] = r.rays;
        j["miss_naive"] = r.miss_naive;
        j["miss_robust"] = r.miss_robust;
        j["miss_embree"] = r.miss_embree;
        j["median_err_naive"] = r.median_err_naive;
        j["median_err_robust"] = r.median_err_robust;
        j["median_err_embree"] = r.median_err_embree;
        j["max_err_naive"] = r.max_err_naive;
        j["max_err_robust"] = r.max_err_robust;
        j["max_err_embree"] = r.max_err_embree;
        a.push_back(std::move(j));
    }
    return a;
}

}  // namespace simdbvh::lab
