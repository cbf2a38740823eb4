#pragma once
// Hit record (16 bytes, the hit-file record): P = (1-u-v) v0 + u v1 + v v2.
#include <bit>
#include <cstdint>
#include <limits>

namespace simdbvh {

inline constexpr std::uint32_t kInvalidPrim = 0xFFFFFFFFu;

struct Hit {
    float t = std::numeric_limits<float>::infinity();
    float u = 0.0f;
    float v = 0.0f;
    std::uint32_t prim = kInvalidPrim;

    constexpr bool hit() const { return prim != kInvalidPrim; }
};
static_assert(sizeof(Hit) == 16);

// Bit equality: our paths must agree to the last bit (same triangle, t, u, v).
inline bool operator==(const Hit& a, const Hit& b) {
    return std::bit_cast<std::uint32_t>(a.t) == std::bit_cast<std::uint32_t>(b.t) &&
           std::bit_cast<std::uint32_t>(a.u) == std::bit_cast<std::uint32_t>(b.u) &&
           std::bit_cast<std::uint32_t>(a.v) == std::bit_cast<std::uint32_t>(b.v) && a.prim == b.prim;
}

// The closest-hit order: smaller t first, ties to the lower triangle id.
constexpr bool closer(float t, std::uint32_t prim, const Hit& best) {
    return t < best.t || (t == best.t && prim < best.prim);
}

}  // namespace simdbvh
