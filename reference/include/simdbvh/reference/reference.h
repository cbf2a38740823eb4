#pragma once
// The accuracy reference (docs/accuracy.md, "Agreement with a reference"): brute
// force over every triangle, the watertight test (Woop, Benthin, Wald 2013)
// evaluated in double on the same float inputs: same permutation (largest |d|
// component becomes z, winding kept), shear constants, edge functions, det and
// t all in double.
//
// Besides the strict double answer, every triangle carries the float error
// bound of the test so the classification can tell a real disagreement from one
// that lies within float rounding of the reference (a ray grazing an edge or a
// vertex, a hit within rounding of tmin/tmax): see TriangleRef.
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "simdbvh/kernels/hit.h"
#include "simdbvh/kernels/ray.h"
#include "simdbvh/kernels/mesh.h"

namespace simdbvh::reference {

inline constexpr double kFloatEps = 0x1p-24;  // unit roundoff of float

// tau = 16 * eps * (|o|inf + |t_ref| * |d|inf) / |d|, eps = 2^-24.
double tolerance(const Ray& ray, double t_ref);

// One triangle in double. Let E_u, E_v, E_w be the double edge functions and
// delta = 32 * eps * M^2 (M: the largest |sheared coordinate| of the three
// vertices relative to the origin) a bound on how far a float evaluation of an
// edge function may land from it (each sheared coordinate is off by <= ~4 eps M,
// each product of two by ~2 * 4 eps M^2, plus 3 roundings; Embree's Pluecker
// form is of the same order).
struct TriangleRef {
    bool hit = false;     // strict: E's of one sign (0 counts for both), det != 0, tmin <= t <= tmax
    bool near = false;    // hit with the E's allowed delta of the wrong sign and the interval widened by slack
    bool robust = false;  // hit with every |E| > delta and t inside the interval by more than slack:
                          // a float method must hit it
    double t = std::numeric_limits<double>::infinity();
    double u = 0, v = 0;  // P = (1-u-v) v0 + u v1 + v v2
    double slack = 0;     // bound on |t_float - t|: tolerance(ray, t) + delta * sum|z_i - t| / |det|
};
// Invalid rays (prepare(ray).valid false) give TriangleRef{} (a miss).
TriangleRef intersect_double(const Ray& ray, const Vec3& v0, const Vec3& v1, const Vec3& v2);

struct RefHit {  // a triangle the reference keeps (near-hit at least)
    std::uint32_t prim = kInvalidPrim;
    double t = 0, u = 0, v = 0, slack = 0;
    bool hit = false;     // strict hit
    bool robust = false;  // robust hit
};

struct Reference {
    bool valid = false;                                  // prepare(ray).valid; invalid rays miss
    double t = std::numeric_limits<double>::infinity();  // t_ref: closest strict hit
    std::uint32_t prim = kInvalidPrim;                   // its triangle, ties to the lower id
    double tau = 0;                                      // tolerance(ray, t); 0 on a miss
    std::vector<RefHit> candidates;                      // every near-hit triangle, sorted by (t, prim)

    bool hit() const { return prim != kInvalidPrim; }
    bool robust_hit() const;  // some triangle is robustly hit: a float method must not miss
    bool near_hit() const { return !candidates.empty(); }
    // The tie-set: every triangle hit with |t - t_ref| <= tau (ids ascending), empty on a miss.
    // "Hit" includes near hits: a ray through a vertex or along an edge strictly
    // hits one triangle of the fan in double, but the float ray is only known to
    // within rounding and a watertight float test may pick any of them at the
    // same t; every one of them is a correct answer.
    std::vector<std::uint32_t> tie_set() const;
    bool in_tie_set(std::uint32_t prim) const;
    const RefHit* find(std::uint32_t prim) const;  // nullptr when the triangle is not near-hit
};

// Closest hit (and everything the classification needs): O(triangles).
Reference reference_intersect(const Mesh& mesh, const Ray& ray);
// Any hit: is some triangle strictly hit in [tmin, tmax]? Stops at the first.
bool reference_occluded(const Mesh& mesh, const Ray& ray);
// The closest strict hit as a Hit (t, u, v rounded to float), or Hit{}.
Hit to_hit(const Reference& ref);

}  // namespace simdbvh::reference
