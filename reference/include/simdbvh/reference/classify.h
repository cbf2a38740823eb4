#pragma once
// Classification of a method's answers against the double reference
// (docs/accuracy.md, "Agreement with a reference"):
//   agree           both miss, or the method hit the reference's closest triangle with |t - t_ref| <= tau
//   tie             an agreement on another triangle of the tie-set
//   leak            the reference hits, the method misses
//   false_hit       the reference misses, the method hits
//   wrong_triangle  the method's triangle is not in the tie-set
//   t_error         right triangle (in the tie-set) but |t - t_ref| > tau
// Each disagreement is also flagged `marginal` when the method's answer is
// within the float error bound of the reference (a ray grazing an edge or a
// vertex, a hit within rounding of tmin/tmax, an ill-conditioned t): the answer
// a float method would give for some perturbation of the ray by rounding. The
// four counts stay strict; `marginal` says how many of them are of that kind.
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "simdbvh/reference/reference.h"
#include "simdbvh/kernels/hit.h"
#include "simdbvh/kernels/ray.h"
#include "simdbvh/kernels/mesh.h"

namespace simdbvh::reference {

enum class Label : std::uint8_t { agree, tie, leak, false_hit, wrong_triangle, t_error };
std::string_view name(Label l);
constexpr bool is_agreement(Label l) { return l == Label::agree || l == Label::tie; }

struct Verdict {
    Label label = Label::agree;
    bool marginal = false;  // disagreements only
};

// Closest hit. Invalid rays: the reference misses (a method must miss).
Verdict classify(const Reference& ref, const Hit& hit);
// Any hit: only hit/miss matters (leak, false_hit or agree).
Verdict classify_occluded(const Reference& ref, bool occluded);

// Counts per label; one ray is counted once. agree and tie are disjoint.
struct Tally {
    std::uint64_t agree = 0, tie = 0;
    std::uint64_t leak = 0, false_hit = 0, wrong_triangle = 0, t_error = 0;
    std::uint64_t marginal = 0;      // disagreements within float error of the reference (subset of the four)
    std::uint64_t invalid_rays = 0;  // rays prepare() rejects (informational: they are classified too)

    void add(Verdict v);
    Tally& operator+=(const Tally& o);
    std::uint64_t agreements() const { return agree + tie; }
    std::uint64_t disagreements() const { return leak + false_hit + wrong_triangle + t_error; }
    std::uint64_t hard_disagreements() const { return disagreements() - marginal; }
    std::uint64_t total() const { return agreements() + disagreements(); }
    double agreement_rate() const { return total() ? double(agreements()) / double(total()) : 1.0; }
    double disagreements_per_million() const { return total() ? 1e6 * double(disagreements()) / double(total()) : 0.0; }
};
inline Tally operator+(Tally a, const Tally& b) { return a += b; }
// "agree=.. tie=.. leak=.. false_hit=.. wrong_triangle=.. t_error=.. (marginal=..) invalid=.."
std::string to_string(const Tally& t);

// Do two answers for the same ray differ? Hit vs miss, another triangle, or
// |t_a - t_b| > tolerance(ray, min t). Rays that do not differ are not sent to
// the reference by compare_methods.
bool differ(const Ray& ray, const Hit& a, const Hit& b);

struct Disagreement {  // one ray on which the two methods differ (closest hit) or disagree (any hit)
    std::size_t ray = 0;
    Verdict a, b;
    double t_ref = 0;  // +inf when the reference misses
    std::uint32_t ref_prim = kInvalidPrim;
};

struct Comparison {
    Tally a, b;                               // over every ray
    std::vector<Disagreement> disagreements;  // rays where a and b differ, ascending
    std::size_t reference_rays = 0;           // rays the reference was needed for (computed or cached)
};

// References already computed, by ray index: share one between comparisons of
// several methods on the SAME mesh and rays (the reference is the costly part).
struct ReferenceCache {
    std::unordered_map<std::size_t, Reference> refs;
};

struct CompareOptions {
    // Also check rays on which both methods give the same answer against the
    // reference (O(rays x triangles)); by default they count as agreements.
    bool reference_all = false;
    ReferenceCache* cache = nullptr;  // optional, see ReferenceCache
};

// Closest hits of two methods (say ours = a, Embree = b) on the same rays.
// Where they differ, both are classified against the reference (computed only
// for those rays); where they do not, both count as agree (or as classified
// when options.reference_all). Throws simdbvh::Error when sizes differ.
Comparison compare_methods(const Mesh& mesh, std::span<const Ray> rays, std::span<const Hit> hits_a,
                           std::span<const Hit> hits_b, const CompareOptions& options = {});
// Any-hit answers (1 = occluded) of two methods on the same rays.
Comparison compare_occluded(const Mesh& mesh, std::span<const Ray> rays, std::span<const std::uint8_t> occluded_a,
                            std::span<const std::uint8_t> occluded_b, const CompareOptions& options = {});
// Any-hit answers as flags: hits[i].hit() -> 1.
std::vector<std::uint8_t> occluded_flags(std::span<const Hit> hits);

}  // namespace simdbvh::reference
