#pragma once
// Accel: no more method than a scene needs. Builds the method the
// cost model (cost_model.h) predicts answers `expected_rays` rays fastest,
// build included: brute force (scalar or 8-wide SIMD), the BVH2 or a wide BVH
// (4, 8, 16), and forwards intersect/occluded to it. A tree is the one its
// class builds from the mesh with the same options (Bvh2::build(mesh, build),
// BvhN::build(mesh, build, wide)), byte for byte. Hits are those of the
// chosen method, bit for bit (and every method agrees with brute force).
#include <span>
#include <variant>

#include "simdbvh/accel/brute_force8.h"
#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/accel/cost_model.h"

namespace simdbvh {

struct AccelOptions {
    int threads = 1;  // build threads, and the thread count the choice assumes for the trace
    Isa isa =
        active_isa();    // its cost model decides; brute8 and the wide BVHs trace with it (unless TraceOptions::isa)
    BuildOptions build;  // the BVH2 (and the BVH2 the wide trees collapse)
    WideOptions wide;    // the wide trees' collapse
    const CostModel* model = nullptr;  // null: cost_model(isa)
};

class Accel {
public:
    Accel() = default;
    // Chooses by the cost model, then builds. Throws simdbvh::Error on a bad mesh.
    static Accel build(const Mesh& mesh, std::size_t expected_rays, const AccelOptions& opts = {});
    // Builds `method` (choice() still holds the predictions; its method is `method`).
    static Accel build(const Mesh& mesh, AccelMethod method, std::size_t expected_rays, const AccelOptions& opts = {});

    const AccelChoice& choice() const { return choice_; }
    AccelMethod method() const { return choice_.method; }
    Isa isa() const { return isa_; }
    double build_ms() const { return build_ms_; }
    // The tree built, when it is a T (Bvh2, Bvh4, Bvh8, Bvh16, BruteForce8), else null.
    template <class T>
    const T* get() const {
        return std::get_if<T>(&impl_);
    }

    friend void intersect(const Accel& a, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& opts);
    friend void occluded(const Accel& a, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& opts);

private:
    struct Brute {  // the scalar brute force holds its own copy of the (small) mesh
        Mesh mesh;
    };
    std::variant<Brute, BruteForce8, Bvh2, Bvh4, Bvh8, Bvh16> impl_;
    AccelChoice choice_;
    Isa isa_ = Isa::scalar;
    double build_ms_ = 0;
};

// TraceOptions: test and threads apply to every method, box and stats to the trees.
void intersect(const Accel& a, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& opts = {});
void occluded(const Accel& a, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& opts = {});

}  // namespace simdbvh
