// Classification against the double reference: see simdbvh/reference/classify.h.
#include "simdbvh/reference/classify.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "simdbvh/kernels/error.h"

namespace simdbvh::reference {
namespace {

// Could a float method return (prim, t) for some rounding-sized perturbation of
// the ray? Its triangle must be near-hit at t (within that triangle's slack) and
// no robustly hit triangle may lie certainly in front of it.
bool plausible_hit(const Reference& ref, const Hit& h) {
    const RefHit* c = ref.find(h.prim);
    if (!c || !(std::fabs(double(h.t) - c->t) <= c->slack)) return false;
    for (const RefHit& q : ref.candidates)
        if (q.robust && q.t + q.slack < c->t - c->slack) return false;
    return true;
}

}  // namespace

std::string_view name(Label l) {
    switch (l) {
    case Label::agree: return "agree";
    case Label::tie: return "tie";
    case Label::leak: return "leak";
    case Label::false_hit: return "false_hit";
    case Label::wrong_triangle: return "wrong_triangle";
    case Label::t_error: return "t_error";
    }
    return "?";
}

Verdict classify(const Reference& ref, const Hit& h) {
    if (!ref.valid) return h.hit() ? Verdict{Label::false_hit, false} : Verdict{Label::agree, false};
    if (!h.hit()) {
        if (!ref.hit()) return {Label::agree, false};
        return {Label::leak, !ref.robust_hit()};
    }
    if (!ref.hit()) return {Label::false_hit, plausible_hit(ref, h)};
    if (!ref.in_tie_set(h.prim)) return {Label::wrong_triangle, plausible_hit(ref, h)};
    // A float t is +inf where the true t exceeds FLT_MAX (tiny directions,
    // kernels/ray.h): that is the float answer, not an error.
    const bool beyond_float = std::isinf(h.t) && ref.t + ref.tau >= double(std::numeric_limits<float>::max());
    if (!beyond_float && !(std::fabs(double(h.t) - ref.t) <= ref.tau)) return {Label::t_error, plausible_hit(ref, h)};
    return {h.prim == ref.prim ? Label::agree : Label::tie, false};
}

Verdict classify_occluded(const Reference& ref, bool occluded) {
    if (!ref.valid) return {occluded ? Label::false_hit : Label::agree, false};
    const bool want = ref.hit();
    if (occluded == want) return {Label::agree, false};
    if (want) return {Label::leak, !ref.robust_hit()};
    return {Label::false_hit, ref.near_hit()};
}

void Tally::add(Verdict v) {
    switch (v.label) {
    case Label::agree: ++agree; break;
    case Label::tie: ++tie; break;
    case Label::leak: ++leak; break;
    case Label::false_hit: ++false_hit; break;
    case Label::wrong_triangle: ++wrong_triangle; break;
    case Label::t_error: ++t_error; break;
    }
    if (!is_agreement(v.label) && v.marginal) ++marginal;
}

Tally& Tally::operator+=(const Tally& o) {
    agree += o.agree;
    tie += o.tie;
    leak += o.leak;
    false_hit += o.false_hit;
    wrong_triangle += o.wrong_triangle;
    t_error += o.t_error;
    marginal += o.marginal;
    invalid_rays += o.invalid_rays;
    return *this;
}

std::string to_string(const Tally& t) {
    return "agree=" + std::to_string(t.agree) + " tie=" + std::to_string(t.tie) + " leak=" + std::to_string(t.leak) +
           " false_hit=" + std::to_string(t.false_hit) + " wrong_triangle=" + std::to_string(t.wrong_triangle) +
           " t_error=" + std::to_string(t.t_error) + " (marginal=" + std::to_string(t.marginal) +
           ") invalid=" + std::to_string(t.invalid_rays);
}

bool differ(const Ray& ray, const Hit& a, const Hit& b) {
    if (a.hit() != b.hit()) return true;
    if (!a.hit()) return false;
    if (a.prim != b.prim) return true;
    const double ta = a.t, tb = b.t;
    return !(std::fabs(ta - tb) <= tolerance(ray, std::min(ta, tb)));
}

namespace {

template <class Same, class Judge>
Comparison compare(const Mesh& mesh, std::span<const Ray> rays, const CompareOptions& options, Same same, Judge judge) {
    Comparison out;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        if (!prepare(rays[i]).valid) {
            ++out.a.invalid_rays;
            ++out.b.invalid_rays;
        }
        const bool d = !same(i);
        if (!d && !options.reference_all) {
            out.a.add({Label::agree, false});
            out.b.add({Label::agree, false});
            continue;
        }
        Reference local;
        const Reference* ref_ptr = &local;
        if (options.cache) {
            auto it = options.cache->refs.find(i);
            if (it == options.cache->refs.end())
                it = options.cache->refs.emplace(i, reference_intersect(mesh, rays[i])).first;
            ref_ptr = &it->second;
        } else {
            local = reference_intersect(mesh, rays[i]);
        }
        const Reference& ref = *ref_ptr;
        ++out.reference_rays;
        const auto [va, vb] = judge(ref, i);
        out.a.add(va);
        out.b.add(vb);
        if (d || !is_agreement(va.label) || !is_agreement(vb.label))
            out.disagreements.push_back(Disagreement{i, va, vb, ref.t, ref.prim});
    }
    return out;
}

}  // namespace

Comparison compare_methods(const Mesh& mesh, std::span<const Ray> rays, std::span<const Hit> hits_a,
                           std::span<const Hit> hits_b, const CompareOptions& options) {
    if (hits_a.size() != rays.size() || hits_b.size() != rays.size())
        throw Error("compare_methods: rays and hits differ in size");
    return compare(
        mesh, rays, options, [&](std::size_t i) { return !differ(rays[i], hits_a[i], hits_b[i]); },
        [&](const Reference& ref, std::size_t i) {
            return std::pair{classify(ref, hits_a[i]), classify(ref, hits_b[i])};
        });
}

Comparison compare_occluded(const Mesh& mesh, std::span<const Ray> rays, std::span<const std::uint8_t> occluded_a,
                            std::span<const std::uint8_t> occluded_b, const CompareOptions& options) {
    if (occluded_a.size() != rays.size() || occluded_b.size() != rays.size())
        throw Error("compare_occluded: rays and results differ in size");
    return compare(
        mesh, rays, options, [&](std::size_t i) { return (occluded_a[i] != 0) == (occluded_b[i] != 0); },
        [&](const Reference& ref, std::size_t i) {
            return std::pair{classify_occluded(ref, occluded_a[i] != 0), classify_occluded(ref, occluded_b[i] != 0)};
        });
}

std::vector<std::uint8_t> occluded_flags(std::span<const Hit> hits) {
    std::vector<std::uint8_t> f(hits.size());
    for (std::size_t i = 0; i < hits.size(); ++i) f[i] = hits[i].hit() ? 1 : 0;
    return f;
}

}  // namespace simdbvh::reference
