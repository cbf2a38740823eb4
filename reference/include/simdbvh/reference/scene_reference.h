#pragma once
// The double-precision reference for scenes, and the classification of a
// method's closest hits against it (the scene form of classify.h). Every
// instance and every primitive, in double: the world ray enters an instance
// through the inverse of its transform computed in double from the float
// matrix (no rounding to float, unlike every float method, ours included);
// triangles by Moller-Trumbore, spheres by the stable quadratic (long double),
// boxes by slabs, planes by (p - o).n / d.n, all in double on the float inputs.
//
// Tolerance: tau = tolerance(ray, t_ref) (reference.h) times the condition
// number of the hit instance's matrix (1 for planes): the float transform of a
// ray moves its hits by about that much; t is compared within tau times the
// object's t_sensitivity (a grazing triangle's t moves more). "Near" hits admit
// the hit point within delta = 16 * 2^-24 * cond * (|o'| + |t| |d'|) (object
// space, infinity norms) of the surface: the triangle's edges (each barycentric
// against delta over the height to its edge), the sphere (closest approach
// within r + delta), the box (grown by delta); "robust" hits are still hits
// that far inside. A generous bound on what float rounding of the transformed
// ray can do, used to flag disagreements as marginal (a ray through a shared
// edge of a small triangle).
//
// Labels, for a method's closest hit against the reference's:
//   agree        both miss, or the reference's object at |t - t_ref| <= tau
//   tie          another object hit (strict or near) within tau of t_ref
//   false_miss   the reference hits, the method misses
//   false_hit    the method's object is not hit (or only near-hit before t_ref - tau), or the reference misses
//   farther_hit  the method's object is hit, but beyond t_ref + tau (it missed the nearest)
//   t_error      a right object (agree or tie) with its t off by more than tau
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "simdbvh/kernels/ray.h"
#include "simdbvh/scene/scene.h"

namespace simdbvh::reference {

enum class SceneLabel : std::uint8_t { agree, tie, false_miss, false_hit, farther_hit, t_error };
std::string_view name(SceneLabel l);

struct ObjectRef {        // one object (instance and primitive, or a plane) against the ray, in double
    bool strict = false;  // hit in [tmin, tmax]
    bool near = false;    // hit with the slack above (strict implies near)
    bool robust = false;  // strict, and still a hit with the slack taken away
    double t = std::numeric_limits<double>::infinity();
    // How much a displacement of the surface along its normal moves t, against a head-on hit: 1 / |cos| of the
    // angle between the ray and a triangle's normal (grazing hits have ill-conditioned t); 1 for the others.
    double t_sensitivity = 1.0;
};

struct SceneReference {
    bool valid = false;  // prepare(ray).valid; invalid rays miss
    double t = std::numeric_limits<double>::infinity();
    std::uint32_t inst = kInvalidPrim,
                  prim = kInvalidPrim;  // closest strict hit, ties by (inst, prim); planes as in SceneHit
    double tau = 0;
    double t_sensitivity = 1.0;  // the closest object's
    bool robust = false;         // the closest object is robustly hit
    bool hit() const { return prim != kInvalidPrim; }
};

// Per-scene data the reference needs (inverses in double, object bounds), built once.
class SceneReferencer {
public:
    explicit SceneReferencer(const SceneDesc& scene);
    SceneReference closest(const Ray& ray) const;
    // One object: inst < instances (prim in its geometry) or a plane (inst = instances + k, prim = k).
    ObjectRef object(const Ray& ray, std::uint32_t inst, std::uint32_t prim) const;
    double cond(std::uint32_t inst) const;  // 1 for planes

    struct Verdict {
        SceneLabel label = SceneLabel::agree;
        bool marginal = false;  // a disagreement the near slack would turn around
    };
    Verdict classify(const Ray& ray, const SceneReference& ref, const SceneHit& hit) const;

    struct InstanceD {
        double inv[3][4];  // world -> object, from the float matrix in double
        double cond = 1;
    };

    struct RayD {  // a ray in double: a world ray, or one mapped into an instance
        double o[3], d[3], tmin, tmax;
    };

private:
    static ObjectRef shape(const RayD& r, const Geometry& g, std::uint32_t prim, double delta, double tau);
    ObjectRef object_in(const Ray& ray, const RayD& r, std::uint32_t inst, std::uint32_t prim) const;

    const SceneDesc* scene_;
    std::vector<InstanceD> inst_;
    std::vector<Aabb> bounds_;  // per geometry, object space
};

struct SceneTally {
    std::uint64_t count[6] = {0, 0, 0, 0, 0, 0};  // by SceneLabel
    std::uint64_t marginal = 0;
    void add(SceneReferencer::Verdict v) {
        ++count[int(v.label)];
        marginal += v.marginal && int(v.label) >= int(SceneLabel::false_miss);
    }
    std::uint64_t disagreements() const { return count[2] + count[3] + count[4] + count[5]; }
};
// "agree=.. tie=.. false_miss=.. false_hit=.. farther_hit=.. t_error=.. (marginal=..)"
std::string to_string(const SceneTally& t);

}  // namespace simdbvh::reference
