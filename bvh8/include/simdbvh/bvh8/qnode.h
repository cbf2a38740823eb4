#pragma once
// Quantized N-wide nodes (Ylitie, Karras, Laine 2017, section 3.1; Embree's
// compressed nodes): the N child boxes as 8-bit steps on a grid of the node,
// per axis origin + q * 2^e, rounded outward. 128 bytes for N = 8 and 256 for
// N = 16, half a NodeN (N = 4 stays at 128: its NodeN is already two lines).
//
// The node test dequantizes each plane as origin + float(q) * 2^e in float
// (the product is exact: q < 256 and a power of two, so a fused multiply-add
// and a multiply then an add give the same value on every ISA), then runs the
// conservative slab test of the full node on that box. The build checks each
// dequantized box contains the child's own box, so the culling stays
// conservative and every hit is the one the full nodes give.
#include <bit>
#include <cstdint>
#include <type_traits>

#include "simdbvh/bvh8/node.h"
#include "simdbvh/kernels/aabb.h"

namespace simdbvh {

// Planes in BoxN's order (lo_x, hi_x, lo_y, hi_y, lo_z, hi_z), each N bytes,
// so plane p of lane i is q[p * N + i]; then the grid and the used slots.
template <int N>
struct QBoxN {
    static_assert(kValidWidth<N>, "node widths: 4, 8, 16");
    using Mask = std::conditional_t<(N <= 8), std::uint8_t, std::uint16_t>;
    std::uint8_t q[6 * N];
    float origin[3];      // the grid's corner per axis (the node's lower bound)
    std::uint8_t exp[3];  // biased exponent of the step: 2^(exp - 127), 1 <= exp <= 254
    Mask valid;           // bit i: slot i holds a child (empty slots never hit)

    // The step of axis a: the float whose bits are exp << 23.
    float scale(int a) const { return std::bit_cast<float>(std::uint32_t(exp[a]) << 23); }
    // Plane p (0..5) of lane i, dequantized; the node test's value, bit for bit.
    float plane(int p, int i) const { return origin[p / 2] + float(q[p * N + i]) * scale(p / 2); }
    Aabb get(int i) const { return {{plane(0, i), plane(2, i), plane(4, i)}, {plane(1, i), plane(3, i), plane(5, i)}}; }
};

template <int N>
struct alignas(64) QNodeN {
    static constexpr int kWidth = N;
    QBoxN<N> boxes;
    ChildN<N> children[N];
};
using QNode4 = QNodeN<4>;
using QNode8 = QNodeN<8>;
using QNode16 = QNodeN<16>;
static_assert(sizeof(QBoxN<8>) == 64 && sizeof(QNode8) == 128);  // 2 cache lines (NodeN: 4)
static_assert(sizeof(QNode16) == 256);                           // 4 (NodeN: 8)
static_assert(sizeof(QNode4) == 128);                            // 2 (as NodeN)

}  // namespace simdbvh
