// SPDX-License-Identifier: MIT
#pragma once
// The sphere precision study (docs/results.md, "Scenes"): how far from the surface the hit point
// of a ray aimed at a unit sphere lands, and how often the ray misses, as the
// sphere gets further from the ray origin (in radii), for the textbook float
// quadratic, the library's hit_sphere (Haines et al. 2019) and Embree's
// RTC_GEOMETRY_TYPE_SPHERE_POINT. scripts/plot_sphere_precision.py draws it.
#include <cstddef>
#include <vector>

#include "lab.h"
#include "report.h"

namespace simdbvh::lab {

struct SpherePrecisionRow {
    double ratio;      // distance from ray origin to sphere centre / radius
    std::size_t rays;  // rays at this ratio (all aimed to hit)
    // per method: fraction of rays that missed (false misses), and the median and max relative hit-point error
    // | |p - c| - r | / r, with p = o + t d evaluated in double from the method's float t, over the rays it hit
    // (NaN, written as null, when a method hit none)
    double miss_naive, miss_robust, miss_embree;
    double median_err_naive, median_err_robust, median_err_embree;
    double max_err_naive, max_err_robust, max_err_embree;
};

// Ratios 10^0.25 .. 10^7 in steps of 10^0.25 (28 rows), rays_per_ratio rays each; deterministic (fixed seed).
// Per ratio: a sphere of radius 1 at c = o + ratio * axis (o random in [-1,1]^3, a random unit axis, both
// rounded to float); every ray starts at o and aims at a random point of the disc of radius 0.9 around c
// perpendicular to the axis, with its direction left unnormalised (aim - o) for even rays and normalised for odd
// ones; tmin = 0, tmax = +inf. A float direction can round off the sphere when the ratio is large: such a ray
// (one the float ray misses in exact arithmetic, checked in long double) is drawn again, so every ray counted
// hits the float sphere and every miss is a false miss.
std::vector<SpherePrecisionRow> sphere_precision_study(std::size_t rays_per_ratio = 2000);

// The rows as a JSON array of objects with the field names above.
Json sphere_precision_json(const std::vector<SpherePrecisionRow>& rows);

}  // namespace simdbvh::lab
