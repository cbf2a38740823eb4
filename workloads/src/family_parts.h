// SPDX-License-Identifier: MIT
#pragma once
// The pieces the ray families share (scene/src only) and one function per
// family (family_*.cpp); families.cpp names them and dispatches.
// Deterministic: own PRNG (SplitMix64), float math with + - * / sqrt sin cos;
// double only where a family says so (offsets are applied in double and
// rounded to float).
#include <string>
#include <vector>

#include "rng.h"
#include "simdbvh/workloads/families.h"

namespace simdbvh::workloads::detail {

inline constexpr float kTwoPi = 6.28318530717958648f;

std::string decade(double v);        // 1e0, 1e3, ...
Vec3 translate(Vec3 p, double off);  // p + (off, off, off) in double, rounded to float
Vec3 in_ball(Rng& rng, float r);     // a point strictly inside the ball of radius r (rejection sampling)
Vec3 unit_vector(Rng& rng);          // uniform on the unit sphere

std::vector<FamilyCase> family_watertight(const FamilyOptions& o);
std::vector<FamilyCase> family_offsets(const FamilyOptions& o);
std::vector<FamilyCase> family_direction_scale(const FamilyOptions& o);
std::vector<FamilyCase> family_axis_aligned(const FamilyOptions& o);
std::vector<FamilyCase> family_surface_start(const FamilyOptions& o);
std::vector<FamilyCase> family_grazing(const FamilyOptions& o);
std::vector<FamilyCase> family_needles(const FamilyOptions& o);
std::vector<FamilyCase> family_degenerate(const FamilyOptions& o);
std::vector<FamilyCase> family_random(const FamilyOptions& o);

}  // namespace simdbvh::workloads::detail
