// Adversarial ray families (docs/accuracy.md): the catalogue (names) and the
// dispatch to one file per family (family_*.cpp; shared pieces in
// family_parts.h, family_geometry.cpp).
#include "simdbvh/workloads/families.h"

#include "family_parts.h"
#include "simdbvh/kernels/error.h"

namespace simdbvh::workloads {

std::string_view name(Family f) {
    switch (f) {
    case Family::watertight: return "watertight";
    case Family::offsets: return "offsets";
    case Family::axis_aligned: return "axis-aligned";
    case Family::surface_start: return "surface-start";
    case Family::grazing: return "grazing";
    case Family::needles: return "needles";
    case Family::degenerate: return "degenerate";
    case Family::random: return "random";
    case Family::direction_scale: return "direction-scale";
    }
    return "?";
}

std::optional<Family> parse_family(std::string_view s) {
    for (Family f : kAllFamilies)
        if (s == name(f)) return f;
    return std::nullopt;
}

std::string_view name(Expect e) {
    switch (e) {
    case Expect::reference: return "reference";
    case Expect::hit: return "hit";
    case Expect::miss: return "miss";
    case Expect::no_self_hit: return "no-self-hit";
    }
    return "?";
}

std::vector<FamilyCase> make_family(Family f, const FamilyOptions& o) {
    switch (f) {
    case Family::watertight: return detail::family_watertight(o);
    case Family::offsets: return detail::family_offsets(o);
    case Family::axis_aligned: return detail::family_axis_aligned(o);
    case Family::surface_start: return detail::family_surface_start(o);
    case Family::grazing: return detail::family_grazing(o);
    case Family::needles: return detail::family_needles(o);
    case Family::degenerate: return detail::family_degenerate(o);
    case Family::random: return detail::family_random(o);
    case Family::direction_scale: return detail::family_direction_scale(o);
    }
    throw Error("unknown ray family");
}

}  // namespace simdbvh::workloads
