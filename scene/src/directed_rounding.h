#pragma once
// Internal: a double rounded to the float below (down) or above (up) it, for
// boxes that must contain what they bound.
#include <cmath>
#include <limits>

namespace simdbvh::scene::detail {

inline float down(double x) {
    float f = static_cast<float>(x);
    if (double(f) > x) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
    return f;
}
inline float up(double x) {
    float f = static_cast<float>(x);
    if (double(f) < x) f = std::nextafter(f, std::numeric_limits<float>::infinity());
    return f;
}

}  // namespace simdbvh::scene::detail
